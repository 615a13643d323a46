// Which rings can see a ground plane inside a segment: the beam of a ring pointing down at
// angle a meets a horizontal surface h under the sensor at horizontal distance h / tan(a).
#pragma once

#include <array>

#include "vlpground/frame.hpp"

namespace vlpground::detail {

/// tan of each ring's depression angle (sensor frame); <= 0 for rings that look up or
/// that have no return in the frame.
using RingSlopes = std::array<float, kLasers>;

/// Measures the rings' elevation from the first valid return of each row (strongest layer).
void measure_ring_slopes(const Frame& frame, RingSlopes& out);

/// Number of rings whose beam meets a surface `height_m` under the sensor at a horizontal
/// distance within [near_m, far_m].
int rings_reaching(const RingSlopes& slopes, float height_m, float near_m, float far_m);

/// Horizontal distances from (px, py) to the nearest point and the farthest corner of the
/// rectangle [x0, x1] x [y0, y1].
void rect_distances(float px, float py, float x0, float x1, float y0, float y1, float& near_m,
                    float& far_m);

}  // namespace vlpground::detail
