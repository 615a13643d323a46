#include "tangents.hpp"

#include <algorithm>
#include <cmath>

namespace vlpground::detail {

namespace {

bool same_row(const Cloud& c, std::size_t a, std::size_t b) {
  return c.layer[a] == c.layer[b] && c.ring[a] == c.ring[b];
}

float chord_sq(const Cloud& c, std::size_t a, std::size_t b) {
  const float dx = c.x[a] - c.x[b], dy = c.y[a] - c.y[b], dz = c.z[a] - c.z[b];
  return dx * dx + dy * dy + dz * dz;
}

bool continuous(const Cloud& c, const TangentParams& p, std::size_t a, std::size_t b) {
  return std::abs(c.range_xy[a] - c.range_xy[b]) <= p.jump_abs_m + p.jump_rel * c.range_xy[a];
}

// Walks from point i in direction `step` (+1/-1) along its row, over invalid cells (absent
// from the cloud) but never across a range discontinuity; stops at the first neighbour at
// least target_chord_m away. Returns i when there is no usable neighbour.
std::size_t walk(const Cloud& c, const TangentParams& p, std::size_t i, int step) {
  // Fast path: jump straight to the neighbour expected at the target chord (from the range
  // and the column angle) when it is in the same row and continuous with i.
  if (p.column_angle_rad > 0) {
    const float spacing = c.range_xy[i] * p.column_angle_rad;
    const auto k =
        static_cast<std::size_t>(std::clamp(std::ceil(p.target_chord_m / std::max(spacing, 1e-4f)),
                                            1.f, static_cast<float>(p.max_span_columns)));
    if (step > 0 ? i + k < c.size() : k <= i) {
      const std::size_t j = step > 0 ? i + k : i - k;
      if (same_row(c, i, j) &&
          std::abs(int{c.column[j]} - int{c.column[i]}) <= p.max_span_columns &&
          continuous(c, p, i, j))
        return j;
    }
  }
  const std::size_t n = c.size();
  std::size_t best = i, prev = i;
  const float target_sq = p.target_chord_m * p.target_chord_m;
  for (std::size_t k = 1;; ++k) {
    if (step < 0 && k > i) break;
    const std::size_t j = step > 0 ? i + k : i - k;
    if (j >= n || !same_row(c, i, j)) break;
    const int span = std::abs(int{c.column[j]} - int{c.column[i]});
    if (span > p.max_span_columns || !continuous(c, p, prev, j)) break;
    best = prev = j;
    if (chord_sq(c, i, j) >= target_sq) break;
  }
  return best;
}

}  // namespace

void compute_tangents(const Cloud& cloud, const TangentParams& params, Tangents& out) {
  const std::size_t n = cloud.size();
  out.x.resize(n);
  out.y.resize(n);
  out.z.resize(n);
  out.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = walk(cloud, params, i, -1);
    const std::size_t b = walk(cloud, params, i, +1);
    const float dx = cloud.x[b] - cloud.x[a], dy = cloud.y[b] - cloud.y[a],
                dz = cloud.z[b] - cloud.z[a];
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (a == b || len < params.min_chord_m) {
      out.x[i] = 0.f;
      out.y[i] = 0.f;
      out.z[i] = kNoTangentZ;
      out.valid[i] = 0;
      continue;
    }
    out.x[i] = dx / len;
    out.y[i] = dy / len;
    out.z[i] = dz / len;
    out.valid[i] = 1;
  }
}

}  // namespace vlpground::detail
