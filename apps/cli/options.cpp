#include "cli/options.hpp"

#include <spdlog/spdlog.h>

#include <charconv>
#include <cmath>
#include <sstream>

namespace vlpground::cli {
namespace {

double parse_double(const std::string& name, const std::string& v) {
  double out = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
  if (ec != std::errc() || end != v.data() + v.size() || !std::isfinite(out)) {
    throw UsageError(name + " expects a number, got '" + v + "'");
  }
  return out;
}

std::vector<double> parse_list(const std::string& name, const std::string& v) {
  std::vector<double> out;
  std::stringstream ss(v);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(parse_double(name, item));
  return out;
}

}  // namespace

Args::Args(int argc, char** argv, const std::vector<OptionSpec>& specs) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.size() < 2 || arg.rfind("--", 0) != 0) {
      if (arg.size() > 1 && arg[0] == '-' && arg != "-h") {
        throw UsageError("unknown option '" + arg + "'");
      }
      if (arg == "-h") {
        values_["--help"] = "";
        continue;
      }
      positionals_.push_back(arg);
      continue;
    }
    std::optional<std::string> inline_value;
    if (const auto eq = arg.find('='); eq != std::string::npos) {
      inline_value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    }
    const OptionSpec* spec = nullptr;
    for (const auto& s : specs) {
      if (arg == s.name) spec = &s;
    }
    if (spec == nullptr) throw UsageError("unknown option '" + arg + "'");
    if (!spec->takes_value) {
      if (inline_value) throw UsageError(arg + " takes no value");
      values_[arg] = "";
    } else if (inline_value) {
      values_[arg] = *inline_value;
    } else {
      if (i + 1 >= argc) throw UsageError(arg + " needs a value");
      values_[arg] = argv[++i];
    }
  }
}

std::string Args::text(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double Args::number(const std::string& name, double fallback, double lo, double hi) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const double v = parse_double(name, it->second);
  if (v < lo || v > hi) {
    std::ostringstream msg;
    msg << name << " must be in [" << lo << ", " << hi << "], got " << it->second;
    throw UsageError(msg.str());
  }
  return v;
}

std::int64_t Args::integer(const std::string& name, std::int64_t fallback, std::int64_t lo,
                           std::int64_t hi) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  std::int64_t v = 0;
  const auto& s = it->second;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) {
    throw UsageError(name + " expects an integer, got '" + s + "'");
  }
  if (v < lo || v > hi) {
    throw UsageError(name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], got " + s);
  }
  return v;
}

std::string describe_options(const std::vector<OptionSpec>& specs) {
  std::string out;
  for (const auto& s : specs) {
    std::string head = std::string("  ") + s.name;
    out += head;
    out += std::string(head.size() < 18 ? 18 - head.size() : 1, ' ');
    out += s.help;
    out += '\n';
  }
  return out;
}

const std::vector<OptionSpec>& detector_option_specs() {
  static const std::vector<OptionSpec> specs = {
      {"--method", true, "M  ground method: tangent (default, the paper's), ransac, lpr"},
      {"--calibration", true, "FILE  ROS-velodyne calibration YAML (default: built-in angles)"},
      {"--extrinsics", true, "x,y,z,roll,pitch,yaw  sensor pose in the vehicle (m, deg)"},
      {"--cut-angle", true, "DEG  azimuth where frames start (default 0)"},
      {"--model", true, "vlp16|hires  decode as this model whatever the product byte says"},
      {"--seed", true, "N  detector random seed (default 1)"},
      {"--min-sensor-height", true,
       "M  ground lies at least this far under the sensor (default 0.5; 0 for a sensor on a "
       "floor or desk)"},
      {"--terrain-refinement", true,
       "on|off  tangent method: follow curved terrain with cells (default on); off = the "
       "paper's four planes alone"},
      {"--log-level", true, "L  trace|debug|info|warn|error|off (default warn)"},
      {"--help", false, "show this help"},
  };
  return specs;
}

const std::vector<OptionSpec>& output_option_specs() {
  static const std::vector<OptionSpec> specs = {
      {"--frames", true, "N  stop after N frames (default: all)"},
      {"--queue", true, "N  frames pending between reader and detector (default 4)"},
      {"--csv", true, "FILE  one row per return (frame,laser_id,ring,return,timestamp_us,...)"},
      {"--pcd", true, "DIR  one binary PCD per frame (x y z intensity ring time label)"},
      {"--png", true, "DIR  one picture per frame: bird's-eye view over the range image"},
      {"--json", false, "print a machine-readable JSON summary instead of the table"},
  };
  return specs;
}

void apply_common_options(const Args& args, PipelineConfig& config) {
  config.detector.method = args.text("--method", "tangent");
  if (config.detector.method != "tangent" && config.detector.method != "ransac" &&
      config.detector.method != "lpr") {
    throw UsageError("--method must be tangent, ransac or lpr, got '" + config.detector.method +
                     "'");
  }
  config.detector.seed = static_cast<std::uint64_t>(
      args.integer("--seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  config.detector.min_sensor_height_m =
      args.number("--min-sensor-height", config.detector.min_sensor_height_m, 0.0,
                  config.detector.max_sensor_height_m - 0.01);
  const std::string refinement = args.text("--terrain-refinement", "on");
  if (refinement != "on" && refinement != "off")
    throw UsageError("--terrain-refinement must be on or off, got '" + refinement + "'");
  config.detector.terrain_refinement = refinement == "on";
  config.decoder.calibration_file = args.text("--calibration", "");
  if (args.has("--model")) {
    const std::string m = args.text("--model", "");
    if (m == "vlp16") {
      config.decoder.force_model = Model::vlp16;
    } else if (m == "hires") {
      config.decoder.force_model = Model::hires;
    } else {
      throw UsageError("--model must be vlp16 or hires, got '" + m + "'");
    }
  }
  config.assembler.cut_angle_deg = args.number("--cut-angle", 0.0, 0.0, 359.999);
  if (args.has("--extrinsics")) {
    const auto v = parse_list("--extrinsics", args.text("--extrinsics", ""));
    if (v.size() != 6) throw UsageError("--extrinsics expects x,y,z,roll,pitch,yaw (6 numbers)");
    config.detector.extrinsics = Extrinsics{v[0], v[1], v[2], v[3], v[4], v[5]};
  }
  config.queue_frames = static_cast<int>(args.integer("--queue", 4, 1, 256));
  config.max_frames = static_cast<std::uint64_t>(
      args.integer("--frames", 0, 0, std::numeric_limits<std::int64_t>::max()));
}

OutputOptions output_options(const Args& args) {
  OutputOptions o;
  o.csv_path = args.text("--csv", "");
  o.pcd_dir = args.text("--pcd", "");
  o.png_dir = args.text("--png", "");
  o.json = args.has("--json");
  o.log_level = args.text("--log-level", "warn");
  return o;
}

void apply_log_level(const std::string& level) {
  const auto l = spdlog::level::from_str(level);
  if (l == spdlog::level::off && level != "off") {
    throw UsageError("--log-level must be trace, debug, info, warn, error or off, got '" + level +
                     "'");
  }
  spdlog::set_level(l);
}

}  // namespace vlpground::cli
