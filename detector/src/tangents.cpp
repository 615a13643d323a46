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
  Index size;
  [[nodiscard]] Index at(Index p) const { return p; }
  [[nodiscard]] bool same_row(Index a, Index b) const {
    return c.layer[a] == c.layer[b] && c.ring[a] == c.ring[b];
  }
};

struct LastRows {
  const Cloud& c;
  Index size;
  [[nodiscard]] Index at(Index p) const { return c.last_rows[p]; }
  [[nodiscard]] bool same_row(Index a, Index b) const { return c.ring[at(a)] == c.ring[at(b)]; }
};

float chord_sq(const Cloud& c, Index a, Index b) {
  const float dx = c.x[a] - c.x[b], dy = c.y[a] - c.y[b], dz = c.z[a] - c.z[b];
  return dx * dx + dy * dy + dz * dz;
}

bool continuous(const Cloud& c, const TangentParams& p, Index a, Index b) {
  return std::abs(c.range_xy[a] - c.range_xy[b]) <= p.jump_abs_m + p.jump_rel * c.range_xy[a];
}

// Walks from position i in direction `step` (+1/-1) along its row, over invalid cells
// (absent from the cloud) but never across a range discontinuity; stops at the first
// neighbour at least target_chord_m away. Returns i when there is no usable neighbour.
template <class Rows>
Index walk(const Rows& rows, const TangentParams& p, Index i, int step) {
  const Cloud& c = rows.c;
  const Index pi = rows.at(i);
  // Fast path: jump straight to the neighbour expected at the target chord (from the range
  // and the column angle) when it is in the same row and continuous with i.
  if (p.column_angle_rad > 0) {
    const float spacing = c.range_xy[pi] * p.column_angle_rad;
    const auto k =
        static_cast<Index>(std::clamp(std::ceil(p.target_chord_m / std::max(spacing, 1e-4f)), 1.f,
                                      static_cast<float>(p.max_span_columns)));
    if (step > 0 ? i + k < rows.size : k <= i) {
      const Index j = step > 0 ? i + k : i - k, pj = rows.at(j);
      if (rows.same_row(i, j) &&
          std::abs(int{c.column[pj]} - int{c.column[pi]}) <= p.max_span_columns &&
          continuous(c, p, pi, pj))
        return j;
    }
  }
  Index best = i, prev = i;
  const float target_sq = p.target_chord_m * p.target_chord_m;
  for (Index k = 1;; ++k) {
    if (step < 0 && k > i) break;
    const Index j = step > 0 ? i + k : i - k;
    if (j >= rows.size || !rows.same_row(i, j)) break;
    const Index pj = rows.at(j);
    const int span = std::abs(int{c.column[pj]} - int{c.column[pi]});
    if (span > p.max_span_columns || !continuous(c, p, rows.at(prev), pj)) break;
    best = prev = j;
    if (chord_sq(c, pi, pj) >= target_sq) break;
  }
  return best;
}

// Central difference of the neighbours found either side of position i (one-sided at ends).
template <class Rows>
void tangent_at(const Rows& rows, const TangentParams& params, Index i, Tangents& out) {
  const Cloud& cloud = rows.c;
  const Index a = rows.at(walk(rows, params, i, -1)), b = rows.at(walk(rows, params, i, +1));
  const Index point = rows.at(i);
  const float dx = cloud.x[b] - cloud.x[a], dy = cloud.y[b] - cloud.y[a],
              dz = cloud.z[b] - cloud.z[a];
  const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (a == b || len < params.min_chord_m) {
    out.x[point] = 0.f;
    out.y[point] = 0.f;
    out.z[point] = kNoTangentZ;
    out.valid[point] = 0;
    return;
  }
  out.x[point] = dx / len;
  out.y[point] = dy / len;
  out.z[point] = dz / len;
  out.valid[point] = 1;
}

}  // namespace

VLPGROUND_VECTOR_CLONES
void compute_tangents(const Cloud& cloud, const TangentParams& params, Tangents& out) {
  const Index n = cloud.size();
  out.x.resize(n);
  out.y.resize(n);
  out.z.resize(n);
  out.valid.resize(n);
  const DirectRows direct{cloud, n};
  const Index own_rows = cloud.deduplicated ? cloud.last_begin : n;
  for (Index i = 0; i < own_rows; ++i) tangent_at(direct, params, i, out);
  if (!cloud.deduplicated) return;
  // A distinct last return: its row as the sensor saw it, twins included.
  const LastRows last{cloud, cloud.last_rows.size()};
  for (Index p = 0; p < last.size; ++p)
    if (cloud.layer[last.at(p)] == 1) tangent_at(last, params, p, out);
}

}  // namespace vlpground::detail
