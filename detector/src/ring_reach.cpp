#include "ring_reach.hpp"

#include <algorithm>
#include <cmath>

namespace vlpground::detail {

void measure_ring_slopes(const Frame& frame, RingSlopes& out) {
  out.fill(0.f);
  const ReturnLayer& layer = frame.layer[0];
  for (int ring = 0; ring < kLasers; ++ring) {
    for (int col = 0; col < frame.columns(); ++col) {
      const std::size_t i = frame.index(ring, col);
      if (layer.valid[i] == 0) continue;
      const float horizontal = std::hypot(layer.x_m[i], layer.y_m[i]);
      if (horizontal > 0.f) out[static_cast<std::size_t>(ring)] = -layer.z_m[i] / horizontal;
      break;
    }
  }
}

int rings_reaching(const RingSlopes& slopes, float height_m, float near_m, float far_m) {
  int count = 0;
  for (const float slope : slopes) {
    if (slope <= 0.f) continue;
    const float distance = height_m / slope;
    count += distance >= near_m && distance <= far_m;
  }
  return count;
}

void rect_distances(float px, float py, float x0, float x1, float y0, float y1, float& near_m,
                    float& far_m) {
  const float dx = std::max({x0 - px, 0.f, px - x1}), dy = std::max({y0 - py, 0.f, py - y1});
  near_m = std::hypot(dx, dy);
  far_m = std::hypot(std::max(std::abs(x0 - px), std::abs(x1 - px)),
                     std::max(std::abs(y0 - py), std::abs(y1 - py)));
}

}  // namespace vlpground::detail
