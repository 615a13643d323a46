#include "frontends/output_options.hpp"

#include <filesystem>
#include <stdexcept>

namespace vlpground::cli {

void add_output_options(CLI::App& cmd, OutputOptions& o) {
  add_csv_options(cmd, o.csv);
  add_pcd_options(cmd, o.pcd);
  add_png_options(cmd, o.png);
  add_mcap_options(cmd, o.mcap);
  add_foxglove_options(cmd, o.foxglove);
  add_ros2_options(cmd, o.ros2);
}

namespace {

// Puts the option name in front of a sink's errors, so every message says which output failed.
class NamedSink : public FrameSink {
 public:
  NamedSink(std::string option, std::unique_ptr<FrameSink> sink)
      : option_(std::move(option)), sink_(std::move(sink)) {}
  void write(const LabelledFrame& f) override {
    named([&] { sink_->write(f); });
  }
  void on_stats(const PipelineStats& s) override { sink_->on_stats(s); }
  void on_position(const PositionPacket& p) override { sink_->on_position(p); }
  void finish() override {
    named([&] { sink_->finish(); });
  }

 private:
  void named(const auto& call) {
    try {
      call();
    } catch (const std::exception& e) {
      throw std::runtime_error(option_ + ": " + e.what());
    }
  }
  std::string option_;
  std::unique_ptr<FrameSink> sink_;
};

void add_sink(std::vector<std::unique_ptr<FrameSink>>& sinks, const char* option,
              const std::string& where, const auto& make) {
  try {
    if (auto sink = make()) sinks.push_back(std::make_unique<NamedSink>(option, std::move(sink)));
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(option) + " " + where + ": " + e.what());
  }
}

}  // namespace

namespace {

std::string with_name_in_file(const std::string& path, const std::string& name,
                              const char* extension) {
  if (path.empty()) return path;
  const std::filesystem::path p(path);
  const std::string ext = p.has_extension() ? p.extension().string() : extension;
  return (p.parent_path() / (p.stem().string() + "." + name + ext)).string();
}

std::string with_name_in_dir(const std::string& dir, const std::string& name) {
  return dir.empty() ? dir : (std::filesystem::path(dir) / name).string();
}

}  // namespace

OutputOptions outputs_for_sensor(const OutputOptions& o, const std::string& name) {
  OutputOptions s = o;
  s.csv.path = with_name_in_file(o.csv.path, name, ".csv");
  s.pcd.dir = with_name_in_dir(o.pcd.dir, name);
  s.png.dir = with_name_in_dir(o.png.dir, name);
  s.mcap.path = with_name_in_file(o.mcap.path, name, ".mcap");
  s.foxglove.sensor = name;
#if VLPGROUND_WITH_ROS2
  for (std::string* topic : {&s.ros2.config.topic, &s.ros2.config.ground_topic,
                             &s.ros2.config.obstacle_topic}) {
    if (!topic->empty()) *topic += "/" + name;
  }
  s.ros2.config.frame_id += "_" + name;
#endif
  return s;
}

std::vector<std::unique_ptr<FrameSink>> make_sinks(const OutputOptions& o,
                                                   const PipelineConfig& config) {
  std::vector<std::unique_ptr<FrameSink>> sinks;
  add_sink(sinks, "--csv", o.csv.path, [&] { return make_csv_sink(o.csv, config); });
  add_sink(sinks, "--pcd", o.pcd.dir, [&] { return make_pcd_sink(o.pcd, config); });
  add_sink(sinks, "--png", o.png.dir, [&] { return make_png_sink(o.png, config); });
  add_sink(sinks, "--mcap", o.mcap.path, [&] { return make_mcap_sink(o.mcap, config); });
  add_sink(sinks, "--foxglove", o.foxglove.listen,
           [&] { return make_foxglove_sink(o.foxglove, config); });
  add_sink(sinks, "--ros2", describe_ros2_destination(o.ros2),
           [&] { return make_ros2_sink(o.ros2, config); });
  return sinks;
}

}  // namespace vlpground::cli
