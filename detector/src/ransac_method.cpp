// Baseline "ransac": vanilla single-plane RANSAC (the paper's "Vanilla RANSAC" comparison).
//
// Fit set: returns within fit_radius_m, sub-sampled on a subsample_cell_m horizontal grid as
// in the paper's experiments. Fit: M = hypotheses planes through 3 random fit-set returns; the
// winner maximises the inlier count |n . x + d| < epsilon (paper eq. 1). The winner is then refit
// once by orthogonal least squares on its inliers (kept only if it has at least as many
// inliers). Label: every return with |n . x + d| < epsilon is ground, else obstacle; height
// is the signed distance to the plane. Randomness: splitmix64 seeded with `seed` at every
// frame, so a frame always gets the same labels whatever was processed before.
#include <cmath>
#include <vector>

#include "baseline_util.hpp"
#include "method.hpp"

namespace vlpground::detail {
namespace {

class RansacMethod final : public Method {
 public:
  explicit RansacMethod(const DetectorConfig& config) : config_(config) {}

  void detect(const Frame& frame, const Cloud& cloud, GroundResult& out) override {
    baseline::reset_result(frame, out);
    select_candidates(cloud);
    const auto epsilon = static_cast<float>(config_.inlier_distance_m);
    Plane plane;
    int inliers = 0;
    const bool found = best_hypothesis(cloud, epsilon, plane, inliers);
    if (found) refit(cloud, epsilon, plane, inliers);
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      baseline::label_point(cloud, i, found ? &plane : nullptr, epsilon, out);
    }
    out.total_inliers = inliers;
    GroundSegment& segment = out.segments[0];
    segment.plane = plane;
    segment.has_ground = found;
    segment.inliers = inliers;
    const auto r = static_cast<float>(config_.fit_radius_m);
    segment.x_min_m = segment.y_min_m = -r;
    segment.x_max_m = segment.y_max_m = r;
  }

 private:
  void select_candidates(const Cloud& cloud) {
    fit_set_.select(cloud, config_.fit_radius_m, config_.subsample_cell_m);
  }

  int count_inliers(const Cloud& cloud, const Plane& p, float epsilon) const {
    int count = 0;
    for (const std::uint32_t i : candidates()) {
      count += std::abs(baseline::signed_distance(p, cloud.x[i], cloud.y[i], cloud.z[i])) < epsilon;
    }
    return count;
  }

  // Plane through three returns; false when they are (nearly) collinear.
  static bool plane_through(const Cloud& cloud, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                            Plane& out) {
    const float ux = cloud.x[b] - cloud.x[a], uy = cloud.y[b] - cloud.y[a],
                uz = cloud.z[b] - cloud.z[a];
    const float vx = cloud.x[c] - cloud.x[a], vy = cloud.y[c] - cloud.y[a],
                vz = cloud.z[c] - cloud.z[a];
    float nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const float norm = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (!(norm > 1e-6f)) return false;
    const float sign = nz < 0 ? -1.0f : 1.0f;
    nx *= sign / norm;
    ny *= sign / norm;
    nz *= sign / norm;
    out = Plane{nx, ny, nz, -(nx * cloud.x[a] + ny * cloud.y[a] + nz * cloud.z[a])};
    return true;
  }

  bool best_hypothesis(const Cloud& cloud, float epsilon, Plane& best, int& best_inliers) const {
    const auto n = static_cast<std::uint32_t>(candidates().size());
    if (n < 3) return false;
    baseline::SplitMix64 rng(config_.seed);
    best_inliers = -1;
    for (int h = 0; h < config_.hypotheses; ++h) {
      const std::uint32_t a = rng.below(n), b = rng.below(n), c = rng.below(n);
      if (a == b || b == c || a == c) continue;  // a wasted draw, as in textbook RANSAC
      Plane p;
      if (!plane_through(cloud, candidates()[a], candidates()[b], candidates()[c], p)) continue;
      const int inliers = count_inliers(cloud, p, epsilon);
      if (inliers > best_inliers) {
        best_inliers = inliers;
        best = p;
      }
    }
    return best_inliers >= 3;
  }

  void refit(const Cloud& cloud, float epsilon, Plane& plane, int& inliers) {
    inlier_idx_.clear();
    for (const std::uint32_t i : candidates()) {
      if (std::abs(baseline::signed_distance(plane, cloud.x[i], cloud.y[i], cloud.z[i])) <
          epsilon) {
        inlier_idx_.push_back(i);
      }
    }
    Plane refined;
    if (!baseline::fit_plane(cloud, inlier_idx_, refined)) return;
    const int refined_inliers = count_inliers(cloud, refined, epsilon);
    if (refined_inliers >= inliers) {
      plane = refined;
      inliers = refined_inliers;
    }
  }

  DetectorConfig config_;
  [[nodiscard]] const std::vector<std::uint32_t>& candidates() const { return fit_set_.indices(); }

  baseline::FitSet fit_set_;
  std::vector<std::uint32_t> inlier_idx_;
};

}  // namespace

std::unique_ptr<Method> make_ransac_method(const DetectorConfig& config) {
  return std::make_unique<RansacMethod>(config);
}

}  // namespace vlpground::detail
