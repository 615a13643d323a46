#include "steep.hpp"

#include <algorithm>
#include <cmath>

namespace vlpground::detail {

namespace {

// [begin, end) of each (layer, ring) row in the cloud (build_cloud order).
void row_bounds(const Cloud& cloud, std::size_t (&begin)[2][kLasers + 1]) {
  const std::size_t n = cloud.size();
  std::size_t i = 0;
  for (int l = 0; l < 2; ++l) {
    for (int ring = 0; ring <= kLasers; ++ring) {
      while (i < n && (cloud.layer[i] < l || (cloud.layer[i] == l && cloud.ring[i] < ring))) ++i;
      begin[l][ring] = i;
    }
  }
}

}  // namespace

void mark_steep(const Cloud& cloud, std::vector<std::uint8_t>& steep) {
  steep.assign(cloud.size(), 0);
  std::size_t begin[2][kLasers + 1];
  row_bounds(cloud, begin);
  for (int l = 0; l < 2; ++l) {
    for (int ring = 0; ring + 1 < kLasers; ++ring) {
      // Two rows sorted by column: pair the returns of the same column.
      std::size_t a = begin[l][ring], b = begin[l][ring + 1];
      const std::size_t a_end = begin[l][ring + 1],
                        b_end = ring + 2 <= kLasers ? begin[l][ring + 2] : b;
      while (a < a_end && b < b_end) {
        if (cloud.column[a] < cloud.column[b]) {
          ++a;
        } else if (cloud.column[b] < cloud.column[a]) {
          ++b;
        } else {
          const float dz = cloud.z[b] - cloud.z[a], dr = cloud.range_xy[b] - cloud.range_xy[a];
          const auto rises = static_cast<std::uint8_t>(std::abs(dz) > std::abs(dr));
          steep[a] |= rises;
          steep[b] |= rises;
          ++a;
          ++b;
        }
      }
    }
  }
}

}  // namespace vlpground::detail
