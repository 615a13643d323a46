// SensorModel::from_calibration_file: the ROS velodyne driver's calibration YAML.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>

#include "vlpground/driver/sensor_model.hpp"

namespace vlpground {
namespace {

class CalibrationReader {
 public:
  explicit CalibrationReader(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& what) const {
    std::string where;
    if (node.IsDefined() && node.Mark().line >= 0) {
      where = ", line " + std::to_string(node.Mark().line + 1);
    }
    throw std::invalid_argument("calibration file '" + path_ + "'" + where + ": " + what);
  }

  /// `map[key]` as a finite number with |value| <= limit; `fallback` when absent.
  double number(const YAML::Node& map, const char* key, double limit, double fallback,
                bool required, const std::string& context) const {
    const YAML::Node node = map[key];
    if (!node.IsDefined() || node.IsNull()) {
      if (required) fail(map, context + ": missing field '" + key + "'");
      return fallback;
    }
    double value = 0.0;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, context + ": field '" + key + "' is not a number");
    }
    if (!std::isfinite(value) || std::abs(value) > limit) {
      fail(node, context + ": field '" + key + "' = " + node.Scalar() +
                     " is out of range (|x| <= " + std::to_string(limit) + ")");
    }
    return value;
  }

  int integer(const YAML::Node& node, const std::string& what) const {
    try {
      return node.as<int>();
    } catch (const YAML::Exception&) {
      fail(node, what + " is not an integer");
    }
  }

  SensorModel read(Model model) const {
    YAML::Node root;
    try {
      root = YAML::LoadFile(path_);
    } catch (const YAML::BadFile&) {
      throw std::invalid_argument("calibration file '" + path_ + "': cannot open");
    } catch (const YAML::ParserException& e) {
      throw std::invalid_argument("calibration file '" + path_ + "', line " +
                                  std::to_string(e.mark.line + 1) + ": " + e.msg);
    }
    if (!root.IsMap()) fail(root, "expected a map with a 'lasers' list");
    SensorModel m = SensorModel::builtin(model);
    if (root["num_lasers"].IsDefined() && integer(root["num_lasers"], "num_lasers") != kLasers) {
      fail(root["num_lasers"], "num_lasers must be 16");
    }
    m.distance_resolution_m = number(root, "distance_resolution", 0.1, 0.002, false, "top level");
    if (m.distance_resolution_m <= 0.0)
      fail(root["distance_resolution"], "distance_resolution must be > 0");
    const YAML::Node lasers = root["lasers"];
    if (!lasers.IsSequence()) fail(root, "missing 'lasers' list");
    if (lasers.size() != static_cast<std::size_t>(kLasers)) {
      fail(lasers, "'lasers' has " + std::to_string(lasers.size()) + " entries, expected 16");
    }
    std::array<bool, kLasers> seen{};
    for (std::size_t i = 0; i < lasers.size(); ++i) read_laser(lasers[i], i, seen, m);
    m.finalize();
    return m;
  }

 private:
  void read_laser(const YAML::Node& entry, std::size_t index, std::array<bool, kLasers>& seen,
                  SensorModel& m) const {
    const std::string context = "lasers[" + std::to_string(index) + "]";
    if (!entry.IsMap()) fail(entry, context + " is not a map");
    if (!entry["laser_id"].IsDefined()) fail(entry, context + ": missing field 'laser_id'");
    const int id = integer(entry["laser_id"], context + ": laser_id");
    if (id < 0 || id >= kLasers) fail(entry["laser_id"], context + ": laser_id out of 0..15");
    auto& was_seen = seen[static_cast<std::size_t>(id)];
    if (was_seen)
      fail(entry["laser_id"], context + ": laser_id " + std::to_string(id) + " repeated");
    was_seen = true;
    constexpr double kRadToDeg = 180.0 / std::numbers::pi;
    auto& laser = m.lasers[static_cast<std::size_t>(id)];
    laser.elevation_deg =
        number(entry, "vert_correction", std::numbers::pi / 4, 0.0, true, context) * kRadToDeg;
    laser.azimuth_offset_deg =
        number(entry, "rot_correction", std::numbers::pi, 0.0, false, context) * kRadToDeg;
    laser.vertical_offset_m = number(entry, "vert_offset_correction", 1.0, 0.0, false, context);
    laser.distance_correction_m = number(entry, "dist_correction", 1.0, 0.0, false, context);
    // Validated but not applied: zero for every VLP-16 calibration published.
    for (const char* key : {"dist_correction_x", "dist_correction_y", "horiz_offset_correction",
                            "focal_distance", "focal_slope"}) {
      number(entry, key, 1000.0, 0.0, false, context);
    }
  }

  std::string path_;
};

}  // namespace

SensorModel SensorModel::from_calibration_file(const std::string& path, Model model) {
  SensorModel m = CalibrationReader(path).read(model);
  m.source = path;
  return m;
}

}  // namespace vlpground
