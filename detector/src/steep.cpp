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

// 1 when points a and b lie on one upright face: within kFaceRange_m of each other in
// horizontal range and rising over 63 degrees (|dz| > 2 |dr|). Across a ring that did not
// return the two lie twice as far apart in height as adjacent rings, so ground at a face's
// foot would rise steeply to it from much farther (a trunk 0.5-1.1 m behind the hillside
// under it, hills_s1805_tilt); on one face they lie at the same range, within its noise.
constexpr float kFaceRange_m = 0.1f;
std::uint8_t on_one_face(const float* z, const float* range, Index a, Index b) {
  const float dz = z[b] - z[a], dr = std::abs(range[b] - range[a]);
  return static_cast<std::uint8_t>((dr < kFaceRange_m) & (std::abs(dz) > 2.f * dr));
}

// Rows as a table: table.point[ring * columns + column] is the cloud point (at(p) of row
// position p) of each ring that returned in the column, where table.present has the ring's
// bit; ring-major, as the rows, so that it is written in order. Positions [first, last).
template <class At>
void tabulate(const Cloud& cloud, Index columns, Index first, Index last, At at, FaceTable& table) {
  table.present.assign(columns, 0);
  table.point.resize(columns * kLasers);
  std::uint16_t* const present = table.present.data();
  std::uint32_t* const point = table.point.data();
  for (Index p = first; p < last; ++p) {
    const Index i = at(p), c = cloud.column[i], ring = cloud.ring[i];
    present[c] = static_cast<std::uint16_t>(present[c] | (1u << ring));
    point[ring * columns + c] = static_cast<std::uint32_t>(i);
  }
}

// Marks both returns of each pair of a column's rings two apart, the ring between without a
// return, that lie on one face (on_one_face); `markable` says which points may be marked.
template <class Markable>
void mark_gaps(const Cloud& cloud, const FaceTable& table, Markable markable,
               std::vector<std::uint8_t>& steep) {
  const Index columns = table.present.size();
  for (Index c = 0; c < columns; ++c) {
    const unsigned rings = table.present[c];
    // Bit r: ring r and ring r + 2 returned, ring r + 1 did not.
    unsigned gaps = rings & ~(rings >> 1) & (rings >> 2);
    while (gaps != 0) {
      const auto r = static_cast<Index>(__builtin_ctz(gaps));
      gaps &= gaps - 1;
      const Index a = table.point[r * columns + c], b = table.point[(r + 2) * columns + c];
      const std::uint8_t face = on_one_face(cloud.z.data(), cloud.range_xy.data(), a, b);
      if (markable(a)) steep[a] |= face;
      if (markable(b)) steep[b] |= face;
    }
  }
}

}  // namespace

void add_faces_across_gaps(const Cloud& cloud, FaceTable& table, std::vector<std::uint8_t>& steep) {
  const Index n = cloud.size();
  const Index strongest = strongest_end(cloud);
  const auto own = [](Index p) { return p; };
  const auto any = [](Index) { return true; };
  // Columns: one past the largest column of any return (a vectorised pass).
  std::uint16_t last_column = 0;
  for (Index i = 0; i < n; ++i) last_column = std::max(last_column, cloud.column[i]);
  const Index columns = n == 0 ? 0 : Index{last_column} + 1;
  tabulate(cloud, columns, 0, strongest, own, table);
  mark_gaps(cloud, table, any, steep);
  if (!cloud.deduplicated) {
    tabulate(cloud, columns, strongest, n, own, table);
    mark_gaps(cloud, table, any, steep);
    return;
  }
  // The last layer as the sensor saw it (twins included); twins keep their strongest-row
  // flag.
  const std::uint32_t* const rows = cloud.last_rows.data();
  tabulate(
      cloud, columns, 0, cloud.last_rows.size(), [rows](Index p) { return Index{rows[p]}; }, table);
  const Index last_begin = cloud.last_begin;
  mark_gaps(
      cloud, table, [last_begin](Index i) { return i >= last_begin; }, steep);
}

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
