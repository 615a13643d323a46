// Baseline "lpr": the ground plane fitting (GPF) module of Zermas et al., "Fast segmentation
// of 3D point clouds: a paradigm on LiDAR data for autonomous vehicle applications",
// ICRA 2017 (Algorithm 1), as the paper's "LPR" comparison uses it.
//
// Segments: three fixed longitudinal segments, equal thirds of [-R, R] along the vehicle x
// axis with R = fit_radius_m: [-R, -R/3), [-R/3, R/3), [R/3, R]. Fitting uses the returns
// within R horizontally, sub-sampled on a subsample_cell_m grid (the paper's protocol for
// every method); labelling covers every return, the ones beyond R taking the segment
// their x falls in (x < -R/3 -> first, x >= R/3 -> last).
// Per segment: sort by height; LPR = mean z of the N_LPR = 20 lowest returns; seeds = the
// returns with z < LPR + Th_seeds (0.4 m); then N_iter = 3 times: fit a plane to the current
// ground set (normal = eigenvector of the smallest covariance eigenvalue), ground = returns
// with |n . x + d| < Th_dist (inlier_distance_m, 0.2 m).
// Too few points: a segment with < 3 returns, or whose seed / ground set has < 3 returns,
// keeps the last plane it managed to fit; with none, it borrows the plane of the nearest
// segment that has one (middle first). With no plane anywhere every return is an obstacle
// with a NaN height.
#include <algorithm>
#include <cmath>
#include <vector>

#include "baseline_util.hpp"
#include "method.hpp"

namespace vlpground::detail {
namespace {

constexpr int kSegments = 3;
constexpr std::size_t kLowestPointCount = 20;  // N_LPR
constexpr float kSeedThresholdM = 0.4f;        // Th_seeds
constexpr int kIterations = 3;                 // N_iter

class LprMethod final : public Method {
 public:
  explicit LprMethod(const DetectorConfig& config) : config_(config) {}

  void detect(const Frame& frame, const Cloud& cloud, GroundResult& out) override {
    baseline::reset_result(frame, out);
    split_segments(cloud);
    const auto threshold = static_cast<float>(config_.inlier_distance_m);
    for (int s = 0; s < kSegments; ++s) {
      fitted_[s] = fit_segment(cloud, segment_[s], threshold, planes_[s], inliers_[s]);
    }
    const auto r = static_cast<float>(config_.fit_radius_m);
    for (int s = 0; s < kSegments; ++s) {
      GroundSegment& g = out.segments[static_cast<std::size_t>(s)];
      g.has_ground = fitted_[s];
      g.plane = planes_[s];
      g.inliers = fitted_[s] ? inliers_[s] : 0;
      g.x_min_m = -r + 2.0f * r * static_cast<float>(s) / kSegments;
      g.x_max_m = -r + 2.0f * r * static_cast<float>(s + 1) / kSegments;
      g.y_min_m = -r;
      g.y_max_m = r;
      out.total_inliers += g.inliers;
    }
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const int s = plane_source(segment_of(cloud.x[i]));
      baseline::label_point(cloud, i, s < 0 ? nullptr : &planes_[s], threshold, out);
    }
  }

 private:
  int segment_of(float x) const {
    const auto third = static_cast<float>(config_.fit_radius_m / 3.0);
    return x < -third ? 0 : (x < third ? 1 : 2);
  }

  // The segment whose plane labels segment `s` (itself, else the nearest fitted one).
  int plane_source(int s) const {
    if (fitted_[s]) return s;
    if (fitted_[1]) return 1;
    for (int t = 0; t < kSegments; ++t) {
      if (fitted_[t]) return t;
    }
    return -1;
  }

  void split_segments(const Cloud& cloud) {
    fit_set_.select(cloud, config_.fit_radius_m, config_.subsample_cell_m);
    // Room for the whole fit set in every segment: how returns spread over the segments
    // changes from frame to frame, the total only grows up to the largest frame.
    const std::size_t n = fit_set_.indices().size();
    for (auto& seg : segment_) {
      seg.clear();
      if (seg.capacity() < n) seg.reserve(n);
    }
    if (ground_.capacity() < n) ground_.reserve(n);
    for (const std::uint32_t i : fit_set_.indices()) segment_[segment_of(cloud.x[i])].push_back(i);
  }

  // Zermas Algorithm 1 on one segment. Returns whether a plane was fitted.
  bool fit_segment(const Cloud& cloud, std::vector<std::uint32_t>& points, float threshold,
                   Plane& plane, int& inliers) {
    if (points.size() < 3) return false;
    std::sort(points.begin(), points.end(),
              [&](std::uint32_t a, std::uint32_t b) { return cloud.z[a] < cloud.z[b]; });
    const std::size_t lowest = std::min(kLowestPointCount, points.size());
    double lpr = 0;
    for (std::size_t k = 0; k < lowest; ++k) lpr += cloud.z[points[k]];
    lpr /= static_cast<double>(lowest);
    const float seed_limit = static_cast<float>(lpr) + kSeedThresholdM;
    ground_.clear();
    for (const std::uint32_t i : points) {
      if (cloud.z[i] >= seed_limit) break;  // sorted by height
      ground_.push_back(i);
    }
    bool fitted = false;
    for (int iteration = 0; iteration < kIterations; ++iteration) {
      if (!baseline::fit_plane(cloud, ground_, plane)) break;
      fitted = true;
      ground_.clear();
      for (const std::uint32_t i : points) {
        if (std::abs(baseline::signed_distance(plane, cloud.x[i], cloud.y[i], cloud.z[i])) <
            threshold) {
          ground_.push_back(i);
        }
      }
    }
    inliers = static_cast<int>(ground_.size());
    return fitted;
  }

  DetectorConfig config_;
  baseline::FitSet fit_set_;
  std::vector<std::uint32_t> segment_[kSegments];  // fitting returns of each segment
  std::vector<std::uint32_t> ground_;
  Plane planes_[kSegments] = {};
  int inliers_[kSegments] = {};
  bool fitted_[kSegments] = {};
};

}  // namespace

std::unique_ptr<Method> make_lpr_method(const DetectorConfig& config) {
  return std::make_unique<LprMethod>(config);
}

}  // namespace vlpground::detail
