// Ground-surface detection on a 16 x N range image (paper: "On Enhancing Ground Surface
// Detection from Sparse Lidar Point Cloud", Li). Methods (GroundMethod): tangent (the
// paper's, default), ransac (single-plane baseline), lpr (Zermas et al. 2017 ground-plane
// fitting).
//
// Thread-safety: a GroundDetector keeps a reusable workspace; use one per thread.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vlpground/frame.hpp"

namespace vlpground {

enum class GroundLabel : std::uint8_t { no_return = 0, ground = 1, obstacle = 2 };

/// Ground detection method.
enum class GroundMethod : std::uint8_t {
  tangent,  // the paper's: tangent-verified RANSAC over four cross-partition segments
  ransac,   // baseline: one RANSAC plane
  lpr,      // baseline: Zermas et al. 2017 lowest-point-representative plane fitting
};

/// "tangent", "ransac", "lpr".
constexpr std::string_view to_string(GroundMethod m) {
  switch (m) {
    case GroundMethod::tangent:
      return "tangent";
    case GroundMethod::ransac:
      return "ransac";
    case GroundMethod::lpr:
      return "lpr";
  }
  return "?";
}

/// The method named `name` (as to_string() spells it); nullopt for anything else.
constexpr std::optional<GroundMethod> parse_ground_method(std::string_view name) {
  for (GroundMethod m : {GroundMethod::tangent, GroundMethod::ransac, GroundMethod::lpr}) {
    if (name == to_string(m)) return m;
  }
  return std::nullopt;
}

/// Sensor-to-vehicle transform applied before fitting (the paper assumes it known).
struct Extrinsics {
  double x_m = 0, y_m = 0, z_m = 0;
  double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
};

/// Vehicle-from-sensor transform: p_vehicle = R p_sensor + t, R = Rz(yaw) Ry(pitch) Rx(roll).
struct RigidTransform {
  float r[3][3];
  float t[3];
};
/// The transform the detector applies to every return (also for drawing points as it sees them).
[[nodiscard]] RigidTransform vehicle_from_sensor(const Extrinsics& e);

struct DetectorConfig {
  GroundMethod method = GroundMethod::tangent;
  Extrinsics extrinsics;
  double fit_radius_m = 40.0;  // returns used for fitting
  int grid_bins = 80;          // B
  double bin_size_m = 1.0;
  int hypotheses = 200;             // M
  double inlier_distance_m = 0.2;   // epsilon
  double tangent_angle_deg = 10.0;  // delta of eq. 3
  int min_segment_inliers = 30;     // T
  double subsample_cell_m = 0.1;    // 0 = no sub-sampling for scoring
  std::uint64_t seed = 1;

  // Plausibility additions to the paper (docs/detector.md says what each one buys).
  double max_tilt_deg = 12.0;          // hypotheses steeper than this are not ground
  double below_distance_m = 0.3;       // a return this far under a plane counts against it
  int below_penalty = 2;               // score = inliers - penalty * returns below (per bin)
  double max_step_m = 0.4;             // segment planes must agree within this at the centre
  double min_sensor_height_m = 0.5;    // the anchor plane must lie this far under the sensor
  double max_sensor_height_m = 5.0;    //   and no farther
  double label_height_m = 0.18;        // labels: ground up to this above the plane (curbs)
  double steep_label_height_m = 0.06;  //   or this for a return on a steep surface (wall, car)
  double label_below_m = 0.5;          //   and down to this under it
  double label_growth_per_m = 0.02;    // beyond fit_radius_m both grow by this per metre

  // Terrain refinement ("tangent" only; docs/detector.md): where the four partition planes
  // do not explain the ground (rolling or curved terrain, embankments), square cells of
  // this side get surfaces of their own, grown outwards from the sensor. false: the paper's
  // method alone.
  bool terrain_refinement = true;
  double refinement_cell_m = 4.0;
  // Column profiles (level 3; docs/detector.md): every column of the range image is walked
  // outwards from the ground under the vehicle and labelled by its own ground profile,
  // checked against the cells' surface and along the rings. Only with method tangent and
  // terrain_refinement (ignored otherwise); false: the cells label.
  bool column_profiles = true;

  /// Throws std::invalid_argument naming the bad field and its valid range.
  void validate() const;
};

/// Plane n . p + d = 0 in the vehicle frame, unit normal with n.z > 0.
struct Plane {
  float nx = 0, ny = 0, nz = 1, d = 0;
};

/// One of the four cross-partition segments (quadrants around the partition centre).
struct GroundSegment {
  Plane plane;
  bool has_ground = false;  // false: no plausible ground plane of its own in this segment
  bool inherited = false;   // plane taken from a neighbouring segment (has_ground false)
  int inliers = 0;
  float x_min_m = 0, x_max_m = 0, y_min_m = 0, y_max_m = 0;  // vehicle frame
};

struct StageTimings {
  double cloud_ms = 0, tangents_ms = 0, hypotheses_ms = 0, inliers_ms = 0, integral_ms = 0,
         search_ms = 0, labelling_ms = 0, total_ms = 0;
};

/// Per-cell output, laid out like the frame (index = ring * stride + col) per layer.
struct GroundResult {
  std::vector<std::uint8_t> label[2];  // GroundLabel values
  std::vector<float> height_m[2];      // height above the fitted ground (NaN if none)
  int stride = 0;
  int columns = 0;
  std::array<GroundSegment, 4> segments{};
  float centre_x_m = 0, centre_y_m = 0;  // partition centre (vehicle frame)
  int total_inliers = 0;
  StageTimings timings;
  std::uint64_t ground_returns = 0, obstacle_returns = 0;

  /// Sizes the arrays for frames of `capacity_columns`; the only allocating call.
  void reserve(int capacity_columns);
};

class GroundDetector {
 public:
  /// Validates `config` (throws std::invalid_argument) and builds the chosen method.
  explicit GroundDetector(const DetectorConfig& config = {});
  ~GroundDetector();
  GroundDetector(GroundDetector&&) noexcept;
  GroundDetector& operator=(GroundDetector&&) noexcept;

  /// Labels every cell of `frame` into `out`. No heap allocation after the first call for a
  /// given frame capacity. Frames are labelled alone, but for one case: a frame that is a
  /// fragment of a rotation (FrameMeta::complete false) going on from the frame detected
  /// just before (the next sequence number, a whole rotation that ended at the cut) is
  /// judged at its edges with that frame's returns (a capture's last frame; the tangent
  /// method's column profiles). So give each sensor's frames, in order, to a detector of
  /// its own.
  void detect(const Frame& frame, GroundResult& out);

  [[nodiscard]] const DetectorConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground
