#include "cli/options.hpp"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <cmath>
#include <limits>
#include <map>

#include "cli/yaml_config.hpp"

namespace vlpground::cli {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

double parse_number(const std::string& option, const std::string& text) {
  const std::string v = trim(text);
  double out = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size() || !std::isfinite(out)) {
    throw CLI::ValidationError(option, "expects a number, got '" + text + "'");
  }
  return out;
}

}  // namespace

Extrinsics parse_extrinsics(const std::vector<std::string>& values) {
  std::vector<double> v;
  for (const auto& value : values) {
    std::string item;
    for (const char c : value + ",") {
      if (c != ',') {
        item += c;
        continue;
      }
      if (!trim(item).empty()) v.push_back(parse_number("--extrinsics", item));
      item.clear();
    }
  }
  if (v.size() != 6) {
    throw CLI::ValidationError("--extrinsics", "expects x,y,z,roll,pitch,yaw (6 numbers), got " +
                                                   std::to_string(v.size()));
  }
  return Extrinsics{v[0], v[1], v[2], v[3], v[4], v[5]};
}

void add_detector_options(CLI::App& cmd, PipelineConfig& config) {
  const char* group = "Detector";
  DetectorConfig& d = config.detector;
  add_choice_option<GroundMethod>(cmd, "--method", d.method,
                                  {{"tangent", GroundMethod::tangent},
                                   {"ransac", GroundMethod::ransac},
                                   {"lpr", GroundMethod::lpr}},
                                  "ground method: tangent (the paper's), ransac, lpr")
      ->group(group);
  cmd.add_option("--calibration", config.decoder.calibration_file,
                 "ROS-velodyne calibration YAML (empty: built-in angles)")
      ->type_name("FILE")
      ->group(group);
  cmd.add_option_function<std::vector<std::string>>(
         "--extrinsics",
         [&d](const std::vector<std::string>& v) { d.extrinsics = parse_extrinsics(v); },
         "sensor pose in the vehicle frame: x,y,z (m), roll,pitch,yaw (deg); the "
         "detector's planes and heights are then in the vehicle frame (CSV/PCD points stay "
         "in the sensor frame). " +
             std::string(kFrameConvention))
      ->type_name("X,Y,Z,ROLL,PITCH,YAW")
      ->expected(1, 6)
      ->default_str("0,0,0,0,0,0")
      ->group(group);
  cmd.add_option("--cut-angle", config.assembler.cut_angle_deg, "azimuth where frames start (deg)")
      ->check(CLI::Range(0.0, 359.999))
      ->group(group);
  cmd.add_option_function<std::string>(
         "--model",
         [&config](const std::string& m) {
           config.decoder.force_model = m == "hires" ? Model::hires : Model::vlp16;
         },
         "decode as this model whatever the product byte says")
      ->check(CLI::IsMember({"vlp16", "hires"}))
      ->default_str("from the product byte")
      ->group(group);
  cmd.add_option("--seed", d.seed, "detector random seed")->group(group);
  cmd.add_option("--min-sensor-height", d.min_sensor_height_m,
                 "ground lies at least this far under the sensor (m; 0 for a sensor on a "
                 "floor or desk)")
      ->check(CLI::Range(0.0, d.max_sensor_height_m - 0.01))
      ->group(group);
  cmd.add_option_function<std::string>(
         "--terrain-refinement",
         [&d](const std::string& v) { d.terrain_refinement = v == "on"; },
         "tangent method: follow rolling and curved terrain with cells (on), or the paper's "
         "four planes alone (off)")
      ->check(CLI::IsMember({"on", "off"}))
      ->default_str("on")
      ->group(group);
  cmd.add_option_function<std::string>(
         "--column-profiles",
         [&d](const std::string& v) { d.column_profiles = v == "on"; },
         "tangent method with terrain refinement: label each column of the range image by "
         "its own ground profile, checked against the cells (on), or by the cells alone (off)")
      ->check(CLI::IsMember({"on", "off"}))
      ->default_str("on")
      ->group(group);
}

void add_frames_option(CLI::App& cmd, std::uint64_t& frames) {
  cmd.add_option_function<std::int64_t>(
         "--frames", [&frames](std::int64_t n) { frames = static_cast<std::uint64_t>(n); },
         "stop after N frames (0 = all); replay and live count full rotations unless --partial")
      ->type_name("N")
      ->check(CLI::Validator(
          [](const std::string& v) {
            return v.find('-') == std::string::npos ? std::string() : "must be >= 0, got " + v;
          },
          ""))
      ->default_str(std::to_string(frames));
}

void add_run_limit_options(CLI::App& cmd, PipelineConfig& config) {
  add_frames_option(cmd, config.max_frames);
  cmd.add_option("--queue", config.queue_frames, "frames pending between reader and detector")
      ->type_name("N")
      ->check(CLI::Range(1, 256));
}

void add_log_level_option(CLI::App& cmd, std::string& level) {
  cmd.add_option("--log-level", level, "log verbosity (logs go to stderr)")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
}

void check_input_file(const std::string& role, const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  const std::string where = role + " " + path + ": ";
  if (!std::filesystem::exists(status)) throw std::runtime_error(where + "no such file");
  if (std::filesystem::is_directory(status)) throw std::runtime_error(where + "is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw std::runtime_error(where + std::strerror(errno));
  std::fclose(f);
}

void apply_log_level(const std::string& level) {
  spdlog::set_level(spdlog::level::from_str(level));
}

}  // namespace vlpground::cli
