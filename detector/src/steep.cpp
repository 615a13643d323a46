#include "steep.hpp"

#include <cmath>

namespace vlpground::detail {

namespace {

bool steep_between(const ReturnLayer& layer, std::size_t a, std::size_t b) {
  if (layer.valid[b] == 0) return false;
  const float dz = layer.z_m[b] - layer.z_m[a];
  const float dr = std::sqrt(layer.x_m[b] * layer.x_m[b] + layer.y_m[b] * layer.y_m[b]) -
                   std::sqrt(layer.x_m[a] * layer.x_m[a] + layer.y_m[a] * layer.y_m[a]);
  return std::abs(dz) > std::abs(dr);
}

}  // namespace

void mark_steep(const Frame& frame, const Cloud& cloud, std::vector<std::uint8_t>& steep) {
  const std::size_t n = cloud.size();
  const auto stride = static_cast<std::size_t>(frame.stride());
  steep.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ReturnLayer& layer = frame.layer[cloud.layer[i]];
    const std::size_t cell = cloud.cell[i];
    const int ring = cloud.ring[i];
    const bool up = ring + 1 < kLasers && steep_between(layer, cell, cell + stride);
    const bool down = !up && ring > 0 && steep_between(layer, cell, cell - stride);
    steep[i] = static_cast<std::uint8_t>(up || down);
  }
}

}  // namespace vlpground::detail
