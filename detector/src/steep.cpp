#include "steep.hpp"

#include <algorithm>
#include <cmath>

namespace vlpground::detail {

namespace {

using Index = std::size_t;

// [begin, end) of each ring's run in a sequence of points sorted by (ring, column):
// begin[ring] for ring in [0, kLasers], with begin[kLasers] = the end of the sequence.
template <class RingOf>
void ring_bounds(Index first, Index last, RingOf ring_of, Index (&begin)[kLasers + 1]) {
  Index i = first;
  for (int ring = 0; ring <= kLasers; ++ring) {
    while (i < last && ring_of(i) < ring) ++i;
    begin[ring] = i;
  }
}

// Pairs the returns of the same column in adjacent rings (two runs sorted by column) and
// marks both when the surface between them rises more than 45 degrees. `point` maps a
// sequence position to its cloud point; only points with `owned` are written.
template <class PointOf, class Owned>
void mark_rows(const Cloud& cloud, const Index (&begin)[kLasers + 1], PointOf point, Owned owned,
               std::vector<std::uint8_t>& steep) {
  for (int ring = 0; ring + 1 < kLasers; ++ring) {
    Index a = begin[ring], b = begin[ring + 1];
    const Index a_end = begin[ring + 1], b_end = begin[ring + 2];
    while (a < a_end && b < b_end) {
      const Index pa = point(a), pb = point(b);
      if (cloud.column[pa] < cloud.column[pb]) {
        ++a;
      } else if (cloud.column[pb] < cloud.column[pa]) {
        ++b;
      } else {
        const float dz = cloud.z[pb] - cloud.z[pa], dr = cloud.range_xy[pb] - cloud.range_xy[pa];
        const auto rises = static_cast<std::uint8_t>(std::abs(dz) > std::abs(dr));
        if (owned(pa)) steep[pa] |= rises;
        if (owned(pb)) steep[pb] |= rises;
        ++a;
        ++b;
      }
    }
  }
}

}  // namespace

void mark_steep(const Cloud& cloud, std::vector<std::uint8_t>& steep) {
  steep.assign(cloud.size(), 0);
  const auto ring_of_point = [&](Index i) { return int{cloud.ring[i]}; };
  const auto itself = [](Index i) { return i; };
  const auto anyone = [](Index) { return true; };
  const Index n = cloud.size();
  Index layer_end[2] = {n, n};
  if (cloud.deduplicated) {
    layer_end[0] = cloud.last_begin;
  } else {
    layer_end[0] = static_cast<Index>(std::find_if(cloud.layer.begin(), cloud.layer.end(),
                                                   [](std::uint8_t l) { return l != 0; }) -
                                      cloud.layer.begin());
  }
  Index begin[kLasers + 1];
  ring_bounds(0, layer_end[0], ring_of_point, begin);
  mark_rows(cloud, begin, itself, anyone, steep);
  if (!cloud.deduplicated) {
    ring_bounds(layer_end[0], n, ring_of_point, begin);
    mark_rows(cloud, begin, itself, anyone, steep);
    return;
  }
  // Last layer as the sensor saw it (twins included); twins keep their strongest-row flag.
  const auto& rows = cloud.last_rows;
  ring_bounds(
      0, rows.size(), [&](Index p) { return int{cloud.ring[rows[p]]}; }, begin);
  mark_rows(
      cloud, begin, [&](Index p) { return Index{rows[p]}; },
      [&](Index i) { return cloud.layer[i] == 1; }, steep);
}

}  // namespace vlpground::detail
