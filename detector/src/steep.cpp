#include "steep.hpp"

#include <algorithm>
#include <cmath>

namespace vlpground::detail {

namespace {

using Index = std::size_t;

// 1 when the surface from point a (lower ring) to b (the ring above) rises over 45 degrees
// (z and range: the cloud's arrays).
std::uint8_t rises_steeply(const float* z, const float* range, Index a, Index b) {
  const float dz = z[b] - z[a], dr = range[b] - range[a];
  return static_cast<std::uint8_t>(std::abs(dz) > std::abs(dr));
}

// Pairs the returns of the same column in adjacent rings (runs sorted by column) and marks
// both when the surface between them rises more than 45 degrees (rises_steeply). Branchless
// merge: the rise of an unpaired a, b is computed too and dropped. The arrays are held in
// locals: a flag is a byte store, which may alias anything, so the cloud's vectors would have
// their pointers reloaded at every step.
void mark_rows(const Cloud& cloud, const RingRuns& begin, std::vector<std::uint8_t>& steep) {
  const float *const z = cloud.z.data(), *const range = cloud.range_xy.data();
  const std::uint16_t* const column = cloud.column.data();
  std::uint8_t* const flag = steep.data();
  for (Index ring = 0; ring + 1 < static_cast<Index>(kLasers); ++ring) {
    Index a = begin[ring], b = begin[ring + 1];
    const Index a_end = begin[ring + 1], b_end = begin[ring + 2];
    while (a < a_end && b < b_end) {
      const std::uint16_t col_a = column[a], col_b = column[b];
      const auto rises = static_cast<std::uint8_t>((col_a == col_b) & rises_steeply(z, range, a, b));
      flag[a] |= rises;
      flag[b] |= rises;
      a += static_cast<Index>(col_a <= col_b);
      b += static_cast<Index>(col_b <= col_a);
    }
  }
}

}  // namespace

void mark_steep(const Cloud& cloud, std::vector<std::uint8_t>& steep) {
  steep.assign(cloud.size(), 0);
  const Index n = cloud.size();
  const Index strongest = strongest_end(cloud);
  mark_rows(cloud, point_ring_runs(cloud, 0, strongest), steep);
  if (!cloud.deduplicated) {
    mark_rows(cloud, point_ring_runs(cloud, strongest, n), steep);
    return;
  }
  // A distinct last return meets the last layer as the sensor saw it (twins included) in
  // the rings below and above; twins keep their strongest-row flag.
  const RingRuns runs = last_row_runs(cloud);
  for (Index i = cloud.last_begin; i < n; ++i) {
    const int ring = cloud.ring[i];
    for (const int other : {ring - 1, ring + 1}) {
      if (other < 0 || other >= kLasers) continue;
      const Index q = last_row_position(cloud, runs, other, cloud.column[i]);
      if (q == cloud.last_rows.size()) continue;
      const Index j = cloud.last_rows[q];
      const Index lower = other < ring ? j : i, upper = other < ring ? i : j;
      steep[i] |= rises_steeply(cloud.z.data(), cloud.range_xy.data(), lower, upper);
    }
  }
}

}  // namespace vlpground::detail
