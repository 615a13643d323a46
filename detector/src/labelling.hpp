// Per-return passes of the tangent method once the partition is chosen: which returns
// support their segment's plane (least-squares refinement), and the final labels. Both are
// branchless loops over the cloud (structure of arrays), cloned for AVX2.
#pragma once

#include <cstdint>
#include <vector>

#include "method.hpp"
#include "tangents.hpp"

namespace vlpground::detail {

/// The four segment planes around the partition centre (segment = (x >= cx) + 2 (y >= cy)).
struct SegmentPlanes {
  Plane plane[4];
  bool usable[4] = {false, false, false, false};
  float cx = 0, cy = 0;
};

/// Per-return facts the passes need besides the cloud.
struct PointFacts {
  const Tangents* tangents = nullptr;
  const std::uint8_t* steep = nullptr;  // 1 = on a steep surface (steep.hpp)
  const std::int32_t* bin = nullptr;    // fitting bin, < 0 = outside the fitting area
};

/// support[i] = segment whose usable plane return i supports by eq. 3 with distance `band`
/// (fitting area only, tangent required, steep returns never), else 4.
void find_support(const Cloud& cloud, const PointFacts& facts, const SegmentPlanes& planes,
                  float band, float sin_delta, std::vector<std::uint8_t>& support);

struct LabelRule {
  float up = 0.18f, steep_up = 0.06f, down = 0.5f;  // height window over the plane
  float growth = 0.02f, radius = 40.f;  // beyond radius the window grows by growth per m
  float sin_label = 0.34f;              // tangent test |n.t| < sin(2 delta)
  float soft_m = 2.f;  // within this of a partition line the plane across may accept too
};

/// ground[i] (0/1) and height[i] of every cloud point (docs/detector.md, "Labels").
void label_points(const Cloud& cloud, const PointFacts& facts, const SegmentPlanes& planes,
                  const LabelRule& rule, std::vector<std::uint8_t>& ground,
                  std::vector<float>& height);

}  // namespace vlpground::detail
