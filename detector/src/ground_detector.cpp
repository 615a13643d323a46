// GroundDetector front end: config validation, cloud building, dispatch to a Method,
// result sizing, timings and counts.
#include "vlpground/detector/ground_detector.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "method.hpp"

namespace vlpground {

namespace {

void require(bool ok, const char* field, const std::string& rule) {
  if (!ok) throw std::invalid_argument(std::string("DetectorConfig.") + field + ": " + rule);
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

void DetectorConfig::validate() const {
  require(to_string(method) != "?", "method",
          "must be tangent, ransac or lpr, got the value " +
              std::to_string(static_cast<int>(method)));
  const Extrinsics& e = extrinsics;
  require(finite(e.x_m) && finite(e.y_m) && finite(e.z_m) && std::abs(e.x_m) <= 100 &&
              std::abs(e.y_m) <= 100 && std::abs(e.z_m) <= 100,
          "extrinsics", "translation must be finite and within 100 m");
  require(finite(e.roll_deg) && finite(e.pitch_deg) && finite(e.yaw_deg) &&
              std::abs(e.roll_deg) <= 180 && std::abs(e.pitch_deg) <= 90 &&
              std::abs(e.yaw_deg) <= 360,
          "extrinsics", "roll in [-180,180], pitch in [-90,90], yaw in [-360,360] degrees");
  require(finite(fit_radius_m) && fit_radius_m > 1 && fit_radius_m <= 200, "fit_radius_m",
          "must be in (1, 200] m");
  require(grid_bins >= 2 && grid_bins <= 1000, "grid_bins", "must be in [2, 1000]");
  require(finite(bin_size_m) && bin_size_m >= 0.1 && bin_size_m <= 20, "bin_size_m",
          "must be in [0.1, 20] m");
  require(hypotheses >= 1 && hypotheses <= 4096, "hypotheses", "must be in [1, 4096]");
  require(finite(inlier_distance_m) && inlier_distance_m > 0 && inlier_distance_m <= 5,
          "inlier_distance_m", "must be in (0, 5] m");
  require(finite(tangent_angle_deg) && tangent_angle_deg > 0 && tangent_angle_deg < 90,
          "tangent_angle_deg", "must be in (0, 90) degrees");
  require(min_segment_inliers >= 0, "min_segment_inliers", "must be >= 0");
  require(finite(subsample_cell_m) && subsample_cell_m >= 0 && subsample_cell_m <= bin_size_m,
          "subsample_cell_m", "must be in [0, bin_size_m] (0 = off)");
  require(finite(max_tilt_deg) && max_tilt_deg > 0 && max_tilt_deg < 60, "max_tilt_deg",
          "must be in (0, 60) degrees");
  require(finite(below_distance_m) && below_distance_m > 0, "below_distance_m", "must be > 0");
  require(below_penalty >= 0 && below_penalty <= 100, "below_penalty", "must be in [0, 100]");
  require(finite(max_step_m) && max_step_m > 0, "max_step_m", "must be > 0");
  require(finite(min_sensor_height_m) && finite(max_sensor_height_m) && min_sensor_height_m >= 0 &&
              max_sensor_height_m > min_sensor_height_m,
          "min_sensor_height_m/max_sensor_height_m", "need 0 <= min < max");
  require(finite(label_height_m) && label_height_m > 0 && label_height_m <= 5, "label_height_m",
          "must be in (0, 5] m");
  require(finite(steep_label_height_m) && steep_label_height_m >= 0 &&
              steep_label_height_m <= label_height_m,
          "steep_label_height_m", "must be in [0, label_height_m] m");
  require(finite(label_below_m) && label_below_m > 0, "label_below_m", "must be > 0");
  require(finite(label_growth_per_m) && label_growth_per_m >= 0 && label_growth_per_m < 1,
          "label_growth_per_m", "must be in [0, 1)");
  require(finite(refinement_cell_m) && refinement_cell_m >= bin_size_m &&
              refinement_cell_m <= 20,
          "refinement_cell_m", "must be in [bin_size_m, 20] m");
}

void GroundResult::reserve(int capacity_columns) {
  const auto cells = static_cast<std::size_t>(kLasers) * static_cast<std::size_t>(capacity_columns);
  for (int l = 0; l < 2; ++l) {
    label[l].assign(cells, static_cast<std::uint8_t>(GroundLabel::no_return));
    height_m[l].assign(cells, std::nanf(""));
  }
  stride = capacity_columns;
  columns = 0;
}

struct GroundDetector::Impl {
  DetectorConfig config;
  std::unique_ptr<detail::Method> method;
  detail::Cloud cloud;
};

namespace {

std::unique_ptr<detail::Method> make_method(const DetectorConfig& config) {
  switch (config.method) {
    case GroundMethod::ransac:
      return detail::make_ransac_method(config);
    case GroundMethod::lpr:
      return detail::make_lpr_method(config);
    case GroundMethod::tangent:
      break;
  }
  return detail::make_tangent_method(config);
}

void reset_cells(const Frame& frame, GroundResult& out) {
  const int layers = frame.layers();
  for (int l = 0; l < 2; ++l) {
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::size_t row = frame.index(ring, 0);
      const auto n = static_cast<std::size_t>(frame.columns());
      std::fill_n(out.label[l].begin() + static_cast<std::ptrdiff_t>(row), n,
                  static_cast<std::uint8_t>(GroundLabel::no_return));
      std::fill_n(out.height_m[l].begin() + static_cast<std::ptrdiff_t>(row), n, std::nanf(""));
    }
    if (l + 1 >= layers) break;
  }
}

}  // namespace

GroundDetector::GroundDetector(const DetectorConfig& config) : impl_(std::make_unique<Impl>()) {
  config.validate();
  impl_->config = config;
  impl_->method = make_method(config);
}

GroundDetector::~GroundDetector() = default;
GroundDetector::GroundDetector(GroundDetector&&) noexcept = default;
GroundDetector& GroundDetector::operator=(GroundDetector&&) noexcept = default;

const DetectorConfig& GroundDetector::config() const { return impl_->config; }

void GroundDetector::detect(const Frame& frame, GroundResult& out) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  if (out.stride != frame.stride()) out.reserve(frame.stride());
  out.columns = frame.columns();
  out.timings = StageTimings{};
  out.segments = {};
  out.total_inliers = 0;
  reset_cells(frame, out);
  // Only the tangent method knows twins (see detail::Cloud); the baselines see every return.
  detail::build_cloud(frame, impl_->config.extrinsics, impl_->config.method == GroundMethod::tangent,
                      impl_->cloud);
  out.timings.cloud_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  impl_->method->detect(frame, impl_->cloud, out);

  std::uint64_t ground = 0, obstacle = 0;
  for (int l = 0; l < frame.layers(); ++l) {
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::uint8_t* row = out.label[l].data() + frame.index(ring, 0);
      for (int col = 0; col < frame.columns(); ++col) {
        ground += row[col] == static_cast<std::uint8_t>(GroundLabel::ground);
        obstacle += row[col] == static_cast<std::uint8_t>(GroundLabel::obstacle);
      }
    }
  }
  out.ground_returns = ground;
  out.obstacle_returns = obstacle;
  out.timings.total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace vlpground
