#include "tangents.hpp"

#include <algorithm>
#include <cmath>

#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

// The points of the cloud in row order: position p holds point at(p). Rows of a cloud are
// its (layer, ring) runs; rows of a deduplicated cloud's last layer are walked through
// Cloud::last_rows, whose entries may be strongest twins (all of one layer, runs by ring).
struct DirectRows {
  const Cloud& c;
  [[nodiscard]] Index at(Index p) const { return p; }
};

struct LastRows {
  const Cloud& c;
  [[nodiscard]] Index at(Index p) const { return c.last_rows[p]; }
};

// One row of the range image: positions [begin, end).
struct RowSpan {
  Index begin, end;
};

float chord_sq(const Cloud& c, Index a, Index b) {
  const float dx = c.x[a] - c.x[b], dy = c.y[a] - c.y[b], dz = c.z[a] - c.z[b];
  return dx * dx + dy * dy + dz * dz;
}

bool continuous(const Cloud& c, const TangentParams& p, Index a, Index b) {
  return std::abs(c.range_xy[a] - c.range_xy[b]) <= p.jump_abs_m + p.jump_rel * c.range_xy[a];
}

// Columns to the neighbour expected at the target chord, from the range and the column
// angle (the fast path of walk); 0 when the fast path is off.
inline std::uint16_t fast_step(float range_xy, const TangentParams& p) {
  if (!(p.column_angle_rad > 0)) return 0;
  const float spacing = range_xy * p.column_angle_rad;
  return static_cast<std::uint16_t>(
      std::clamp(std::ceil(p.target_chord_m / std::max(spacing, 1e-4f)), 1.f,
                 static_cast<float>(p.max_span_columns)));
}

// Walks from position i of `row` in direction `step` (+1/-1) along it, over invalid cells
// (absent from the cloud) but never across a range discontinuity; stops at the first
// neighbour at least target_chord_m away. Returns i when there is no usable neighbour.
// k = fast_step of i: first try the neighbour expected at the target chord, taken when it
// is in the row and continuous with i.
template <class Rows>
Index walk(const Rows& rows, const TangentParams& p, RowSpan row, Index i, int step, Index k) {
  const Cloud& c = rows.c;
  const Index pi = rows.at(i);
  const Index room = step > 0 ? row.end - 1 - i : i - row.begin;  // positions left in the row
  if (k > 0 && k <= room) {
    const Index j = step > 0 ? i + k : i - k, pj = rows.at(j);
    if (std::abs(int{c.column[pj]} - int{c.column[pi]}) <= p.max_span_columns &&
        continuous(c, p, pi, pj))
      return j;
  }
  Index best = i, prev = i;
  const float target_sq = p.target_chord_m * p.target_chord_m;
  for (Index s = 1; s <= room; ++s) {
    const Index j = step > 0 ? i + s : i - s;
    const Index pj = rows.at(j);
    const int span = std::abs(int{c.column[pj]} - int{c.column[pi]});
    if (span > p.max_span_columns || !continuous(c, p, rows.at(prev), pj)) break;
    best = prev = j;
    if (chord_sq(c, pi, pj) >= target_sq) break;
  }
  return best;
}

// Chord between the neighbours found either side of position i (one-sided at ends) into
// out.x/y/z of its point, valid = 1 when there are two distinct neighbours; normalise()
// makes it the tangent.
template <class Rows>
void chord_at(const Rows& rows, const TangentParams& params, RowSpan row, Index i, Index k,
              Tangents& out) {
  const Cloud& cloud = rows.c;
  const Index a = rows.at(walk(rows, params, row, i, -1, k));
  const Index b = rows.at(walk(rows, params, row, i, +1, k));
  const Index point = rows.at(i);
  out.x[point] = cloud.x[b] - cloud.x[a];
  out.y[point] = cloud.y[b] - cloud.y[a];
  out.z[point] = cloud.z[b] - cloud.z[a];
  out.valid[point] = static_cast<std::uint8_t>(a != b);
}

VLPGROUND_VECTOR_CLONES
void fast_steps(const float* __restrict range, std::size_t n, const TangentParams params,
                std::uint16_t* __restrict step) {
  for (Index i = 0; i < n; ++i) step[i] = fast_step(range[i], params);
}

// Central difference / its length; too short a baseline (or none) is no tangent.
VLPGROUND_VECTOR_CLONES
void normalise(std::size_t n, float min_chord, float* __restrict x, float* __restrict y,
               float* __restrict z, std::uint8_t* __restrict valid) {
  for (Index i = 0; i < n; ++i) {
    const float dx = x[i], dy = y[i], dz = z[i];
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool ok = (valid[i] != 0) & !(len < min_chord);
    // Divided unconditionally (a zero length gives a NaN that is not kept) so that the
    // loop vectorises.
    const float tx = dx / len, ty = dy / len, tz = dz / len;
    x[i] = ok ? tx : 0.f;
    y[i] = ok ? ty : 0.f;
    z[i] = ok ? tz : kNoTangentZ;
    valid[i] = static_cast<std::uint8_t>(ok);
  }
}

}  // namespace

VLPGROUND_VECTOR_CLONES
void compute_tangents(const Cloud& cloud, const TangentParams& params, Tangents& out) {
  const Index n = cloud.size();
  out.x.resize(n);
  out.y.resize(n);
  out.z.resize(n);
  out.valid.resize(n);
  out.step.resize(n);
  fast_steps(cloud.range_xy.data(), n, params, out.step.data());
  const DirectRows direct{cloud};
  const Index own_rows = cloud.deduplicated ? cloud.last_begin : n;
  const Index layer_end = strongest_end(cloud);
  for (const RowSpan layer : {RowSpan{0, layer_end}, RowSpan{layer_end, own_rows}}) {
    const RingRuns runs = point_ring_runs(cloud, layer.begin, layer.end);
    for (Index r = 0; r + 1 < runs.size(); ++r) {
      const RowSpan row{runs[r], runs[r + 1]};
      for (Index i = row.begin; i < row.end; ++i) chord_at(direct, params, row, i, out.step[i], out);
    }
  }
  if (cloud.deduplicated) {
    // A distinct last return: its row as the sensor saw it, twins included.
    const LastRows last{cloud};
    const RingRuns runs = last_row_runs(cloud);
    for (Index i = cloud.last_begin; i < n; ++i) {
      const Index p = last_row_position(cloud, runs, cloud.ring[i], cloud.column[i]);
      const Index ring = cloud.ring[i];
      const RowSpan row{runs[ring], runs[ring + 1]};
      chord_at(last, params, row, p, out.step[i], out);
    }
  }
  normalise(n, params.min_chord_m, out.x.data(), out.y.data(), out.z.data(), out.valid.data());
}

}  // namespace vlpground::detail
