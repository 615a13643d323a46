// Helpers shared by the baseline methods (ransac, lpr): output reset, plane fitting by the
// covariance eigenvector, labelling. Internal, not installed.
#pragma once

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "method.hpp"

namespace vlpground::detail::baseline {

/// Marks every cell of every layer in use as `no_return` with a NaN height and clears the
/// per-frame summary, so cells without a return are labelled as the contract requires.
inline void reset_result(const Frame& frame, GroundResult& out) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (int l = 0; l < frame.layers(); ++l) {
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::size_t row = frame.index(ring, 0);
      const auto columns = static_cast<std::size_t>(frame.columns());
      std::fill_n(out.label[l].begin() + static_cast<std::ptrdiff_t>(row), columns,
                  static_cast<std::uint8_t>(GroundLabel::no_return));
      std::fill_n(out.height_m[l].begin() + static_cast<std::ptrdiff_t>(row), columns, kNaN);
    }
  }
  out.stride = frame.stride();
  out.columns = frame.columns();
  out.segments = {};
  out.total_inliers = 0;
  out.ground_returns = 0;
  out.obstacle_returns = 0;
}

inline float signed_distance(const Plane& p, float x, float y, float z) {
  return p.nx * x + p.ny * y + p.nz * z + p.d;
}

/// Labels cloud point `i`: ground when |distance| < threshold; height = signed distance
/// (NaN when there is no plane: the point is then an obstacle).
inline void label_point(const Cloud& cloud, std::size_t i, const Plane* plane, float threshold,
                        GroundResult& out) {
  const int l = cloud.layer[i];
  const std::size_t cell = cloud.cell[i];
  float height = std::numeric_limits<float>::quiet_NaN();
  bool ground = false;
  if (plane != nullptr) {
    height = signed_distance(*plane, cloud.x[i], cloud.y[i], cloud.z[i]);
    ground = std::abs(height) < threshold;
  }
  out.label[l][cell] =
      static_cast<std::uint8_t>(ground ? GroundLabel::ground : GroundLabel::obstacle);
  out.height_m[l][cell] = height;
  ++(ground ? out.ground_returns : out.obstacle_returns);
}

/// Least-squares (orthogonal) plane through the points `idx` of `cloud`: normal = eigenvector
/// of the smallest eigenvalue of their covariance, through their mean; n.z >= 0. Returns
/// false for fewer than 3 points or a degenerate (collinear) set.
inline bool fit_plane(const Cloud& cloud, std::span<const std::uint32_t> idx, Plane& out) {
  if (idx.size() < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const std::uint32_t i : idx) mean += Eigen::Vector3d(cloud.x[i], cloud.y[i], cloud.z[i]);
  mean /= static_cast<double>(idx.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const std::uint32_t i : idx) {
    const Eigen::Vector3d d = Eigen::Vector3d(cloud.x[i], cloud.y[i], cloud.z[i]) - mean;
    cov.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::Vector3d ev = solver.eigenvalues();          // ascending
  if (ev(2) <= 0.0 || ev(1) <= 1e-9 * ev(2)) return false;  // all points on a line (or one)
  Eigen::Vector3d n = solver.eigenvectors().col(0);
  if (n.z() < 0) n = -n;
  out.nx = static_cast<float>(n.x());
  out.ny = static_cast<float>(n.y());
  out.nz = static_cast<float>(n.z());
  out.d = static_cast<float>(-n.dot(mean));
  return true;
}

/// The fitting set of a baseline: returns within `radius_m` horizontally, thinned to the first
/// return of every `cell_m` x `cell_m` horizontal grid cell (the paper's 0.1 m sub-sampling;
/// cell_m = 0 keeps them all). Buffers are kept between frames; a frame stamp avoids clearing
/// the occupancy grid.
class FitSet {
 public:
  void select(const Cloud& cloud, double radius_m, double cell_m) {
    indices_.clear();
    const auto radius = static_cast<float>(radius_m);
    const bool thin = cell_m > 0;
    int side = 0;
    if (thin) {
      side = static_cast<int>(std::ceil(2.0 * radius_m / cell_m)) + 1;
      const auto cells = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
      if (stamp_.size() != cells) stamp_.assign(cells, 0);
      if (++frame_ == 0) {  // wrapped: forget every old stamp
        std::fill(stamp_.begin(), stamp_.end(), 0u);
        frame_ = 1;
      }
    }
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      if (!(cloud.range_xy[i] < radius)) continue;
      if (thin) {
        // Clamped: range_xy is measured from the sensor, x / y from the vehicle origin, so a
        // sensor mounted off the origin puts some fit-set returns just outside [-R, R].
        const auto gx = static_cast<std::size_t>(
            std::clamp(std::floor((cloud.x[i] + radius_m) / cell_m), 0.0, side - 1.0));
        const auto gy = static_cast<std::size_t>(
            std::clamp(std::floor((cloud.y[i] + radius_m) / cell_m), 0.0, side - 1.0));
        std::uint32_t& stamp = stamp_[gy * static_cast<std::size_t>(side) + gx];
        if (stamp == frame_) continue;
        stamp = frame_;
      }
      indices_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  [[nodiscard]] const std::vector<std::uint32_t>& indices() const { return indices_; }

 private:
  std::vector<std::uint32_t> indices_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t frame_ = 0;
};

/// splitmix64 (Steele, Lea, Flood 2014): a tiny PRNG whose sequence is the same on every
/// platform and standard library, unlike std::uniform_int_distribution.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, n) by the multiply-shift reduction (bias < n / 2^32, negligible here).
  std::uint32_t below(std::uint32_t n) {
    return static_cast<std::uint32_t>(((next() >> 32) * static_cast<std::uint64_t>(n)) >> 32);
  }

 private:
  std::uint64_t state_;
};

}  // namespace vlpground::detail::baseline
