#include "tangents.hpp"

#include <algorithm>
#include <cmath>

#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

// The cloud's arrays that the walk reads, held as plain pointers: the tangent's validity is
// a byte store, which may alias anything, so pointers read through the cloud's vectors would
// be reloaded at every return.
struct Points {
  const float *x, *y, *z, *range;
  const std::uint16_t* column;
};

// Where chord_at writes: the chord (later the tangent) and its validity, by cloud point.
struct Chords {
  float *x, *y, *z;
  std::uint8_t* valid;
};

// The points of the cloud in row order: position p holds point at(p). Rows of a cloud are
// its (layer, ring) runs; rows of a deduplicated cloud's last layer are walked through
// Cloud::last_rows, whose entries may be strongest twins (all of one layer, runs by ring).
struct DirectRows {
  Points c;
  [[nodiscard]] Index at(Index p) const { return p; }
};

struct LastRows {
  Points c;
  const std::uint32_t* last_rows;
  [[nodiscard]] Index at(Index p) const { return last_rows[p]; }
};

// One row of the range image: positions [begin, end).
struct RowSpan {
  Index begin, end;
};

float chord_sq(const Points& c, Index a, Index b) {
  const float dx = c.x[a] - c.x[b], dy = c.y[a] - c.y[b], dz = c.z[a] - c.z[b];
  return dx * dx + dy * dy + dz * dz;
}

bool continuous(const Points& c, const TangentParams& p, Index a, Index b) {
  return std::abs(c.range[a] - c.range[b]) <= p.jump_abs_m + p.jump_rel * c.range[a];
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
  const Points& c = rows.c;
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
              const Chords& out) {
  const Points& cloud = rows.c;
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

// Position of each return's neighbour in direction `step` along its row (walk), for the
// rows' positions [row.begin, row.end): one direction at a time, so that the walk's state
// fits in registers.
void walk_rows(const DirectRows& rows, const TangentParams& p, const RingRuns& runs, int step,
               const std::uint16_t* __restrict steps, std::uint32_t* __restrict neighbour) {
  for (Index r = 0; r + 1 < runs.size(); ++r) {
    const RowSpan row{runs[r], runs[r + 1]};
    for (Index i = row.begin; i < row.end; ++i)
      neighbour[i] = static_cast<std::uint32_t>(walk(rows, p, row, i, step, steps[i]));
  }
}

// Chords of points [begin, end) between their neighbours a (before) and b (after), valid
// when they are distinct (chord_at, for points whose rows are their own).
void chords_between(const Points& c, Index begin, Index end, const std::uint32_t* __restrict a,
                    const std::uint32_t* __restrict b, const Chords& out) {
  float* __restrict x = out.x;
  float* __restrict y = out.y;
  float* __restrict z = out.z;
  std::uint8_t* __restrict valid = out.valid;
  for (Index i = begin; i < end; ++i) {
    x[i] = c.x[b[i]] - c.x[a[i]];
    y[i] = c.y[b[i]] - c.y[a[i]];
    z[i] = c.z[b[i]] - c.z[a[i]];
    valid[i] = static_cast<std::uint8_t>(a[i] != b[i]);
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
  out.before.resize(n);
  out.after.resize(n);
  const TangentParams p = params;  // a local: never reloaded after a store
  fast_steps(cloud.range_xy.data(), n, p, out.step.data());
  const std::uint16_t* const steps = out.step.data();
  const Points points{cloud.x.data(), cloud.y.data(), cloud.z.data(), cloud.range_xy.data(),
                      cloud.column.data()};
  const Chords chords{out.x.data(), out.y.data(), out.z.data(), out.valid.data()};
  const DirectRows direct{points};
  const Index own_rows = cloud.deduplicated ? cloud.last_begin : n;
  const Index layer_end = strongest_end(cloud);
  for (const RowSpan layer : {RowSpan{0, layer_end}, RowSpan{layer_end, own_rows}}) {
    const RingRuns runs = point_ring_runs(cloud, layer.begin, layer.end);
    walk_rows(direct, p, runs, -1, steps, out.before.data());
    walk_rows(direct, p, runs, +1, steps, out.after.data());
  }
  chords_between(points, 0, own_rows, out.before.data(), out.after.data(), chords);
  if (cloud.deduplicated) {
    // A distinct last return: its row as the sensor saw it, twins included.
    const LastRows last{points, cloud.last_rows.data()};
    const RingRuns runs = last_row_runs(cloud);
    for (Index i = cloud.last_begin; i < n; ++i) {
      const Index at = last_row_position(cloud, runs, cloud.ring[i], cloud.column[i]);
      const Index ring = cloud.ring[i];
      const RowSpan row{runs[ring], runs[ring + 1]};
      chord_at(last, p, row, at, steps[i], chords);
    }
  }
  normalise(n, p.min_chord_m, out.x.data(), out.y.data(), out.z.data(), out.valid.data());
}

}  // namespace vlpground::detail
