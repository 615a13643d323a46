#include "hypotheses.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace vlpground::detail {

void PlaneSet::clear() {
  nx.clear();
  ny.clear();
  nz.clear();
  d.clear();
}

void PlaneSet::push(const Plane& p) {
  nx.push_back(p.nx);
  ny.push_back(p.ny);
  nz.push_back(p.nz);
  d.push_back(p.d);
}

bool plane_from_points(const float* a, const float* b, const float* c, Plane& out,
                       float min_area_m2) {
  const float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  float n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len >= 2.0f * min_area_m2) || len == 0.f) return false;  // |u x v| = 2 * area
  const float s = (n[2] < 0 ? -1.0f : 1.0f) / len;
  for (float& k : n) k *= s;
  out = {n[0], n[1], n[2], -(n[0] * a[0] + n[1] * a[1] + n[2] * a[2])};
  return true;
}

namespace {

bool tangent_fits(const LowPoints& low, std::size_t i, const Plane& p, float sin_delta) {
  return std::abs(p.nx * low.tx[i] + p.ny * low.ty[i] + p.nz * low.tz[i]) < sin_delta;
}

// A draw in [0, span): Rng::below, with the default reach's span as a constant divisor,
// which the compiler turns into a multiplication (the same value, without a 64-bit division).
std::size_t offset_draw(Rng& rng, std::size_t span) {
  constexpr auto kDefaultSpan = static_cast<std::size_t>(2 * SamplingParams{}.neighbour_bins + 1);
  return span == kDefaultSpan ? rng.below(kDefaultSpan) : rng.below(span);
}

// A low point of a bin within `reach` bins of (col, row), or -1. Always two draws (column,
// row); the row's is only stepped over when the column is off the grid.
std::int32_t neighbour(const LowPoints& low, const SamplingParams& sp, Rng& rng, int col, int row) {
  const int reach = sp.neighbour_bins;
  const auto span = static_cast<std::size_t>(2 * reach + 1);
  const int c = col + static_cast<int>(offset_draw(rng, span)) - reach;
  if (c < 0 || c >= sp.bins) {
    rng.skip(1);
    return -1;
  }
  const int r = row + static_cast<int>(offset_draw(rng, span)) - reach;
  if (r < 0 || r >= sp.bins) return -1;
  return low.slot_of_bin[static_cast<std::size_t>(r * sp.bins + c)];
}

}  // namespace

void sample_hypotheses(const LowPoints& low, const SamplingParams& sp, PlaneSet& out) {
  out.clear();
  const std::size_t n = low.x.size();
  if (n < 3) return;
  Rng rng(sp.seed);
  const int max_attempts = 50 * sp.hypotheses;
  for (int attempt = 0; attempt < max_attempts && out.size() < std::size_t(sp.hypotheses);
       ++attempt) {
    const std::size_t i0 = rng.below(n);
    const std::int32_t i1 = neighbour(low, sp, rng, low.col[i0], low.row[i0]);
    if (i1 < 0) {
      rng.skip(2);  // the third point's draws, which would go unused
      continue;
    }
    const std::int32_t i2 = neighbour(low, sp, rng, low.col[i0], low.row[i0]);
    if (i2 < 0) continue;
    const std::size_t idx[3] = {i0, static_cast<std::size_t>(i1), static_cast<std::size_t>(i2)};
    float pts[3][3];
    for (int k = 0; k < 3; ++k) {
      pts[k][0] = low.x[idx[k]];
      pts[k][1] = low.y[idx[k]];
      pts[k][2] = low.z[idx[k]];
    }
    Plane p;
    if (!plane_from_points(pts[0], pts[1], pts[2], p, sp.min_area_m2)) continue;
    if (p.nz < sp.min_nz) continue;  // tilt prior
    if (!tangent_fits(low, idx[0], p, sp.sin_delta) ||
        !tangent_fits(low, idx[1], p, sp.sin_delta) || !tangent_fits(low, idx[2], p, sp.sin_delta))
      continue;
    out.push(p);
  }
}

bool PlaneFit::solve(Plane& out) const {
  if (n_ < 3) return false;
  const double inv = 1.0 / n_;
  const double m[3] = {s_[0] * inv, s_[1] * inv, s_[2] * inv};
  Eigen::Matrix3d cov;
  cov(0, 0) = ss_[0] * inv - m[0] * m[0];
  cov(0, 1) = cov(1, 0) = ss_[1] * inv - m[0] * m[1];
  cov(0, 2) = cov(2, 0) = ss_[2] * inv - m[0] * m[2];
  cov(1, 1) = ss_[3] * inv - m[1] * m[1];
  cov(1, 2) = cov(2, 1) = ss_[4] * inv - m[1] * m[2];
  cov(2, 2) = ss_[5] * inv - m[2] * m[2];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  if (eig.info() != Eigen::Success || eig.eigenvalues()(1) < 1e-6) return false;
  Eigen::Vector3d n = eig.eigenvectors().col(0);
  if (n.z() < 0) n = -n;
  out = {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z()),
         static_cast<float>(-n.dot(Eigen::Vector3d(m[0], m[1], m[2])))};
  return true;
}

}  // namespace vlpground::detail
