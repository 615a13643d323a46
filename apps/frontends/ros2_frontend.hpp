// --ros2: every labelled frame as a ROS 2 sensor_msgs/PointCloud2 over DDS (docs/ros2.md).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "frontends/frame_sink.hpp"
#if VLPGROUND_WITH_ROS2
#include "vlpground/ros2/publisher.hpp"
#endif

namespace vlpground::cli {

// Without Cyclone DDS at build time (VLPGROUND_WITH_ROS2 off) only --ros2 exists, and it
// fails with the reason.
struct Ros2Options {
  bool enabled = false;
#if VLPGROUND_WITH_ROS2
  ros2::Ros2Config config;  // topic, frame id, domain: the library's defaults
  std::string qos = "reliable";
  unsigned wait_subscribers = 0;  // wait for this many subscribers before the first frame
  double wait_timeout_s = 10.0;   //   at most this long, then fail
#endif
};

void add_ros2_options(CLI::App& cmd, Ros2Options& o);
/// "TOPIC (domain N)" for error messages.
std::string describe_ros2_destination(const Ros2Options& o);
/// nullptr unless --ros2; throws std::runtime_error (DDS) or std::invalid_argument (options).
std::unique_ptr<FrameSink> make_ros2_sink(const Ros2Options& o, const PipelineConfig& config);

}  // namespace vlpground::cli
