#include "frontends/ros2_frontend.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace vlpground::cli {
#if VLPGROUND_WITH_ROS2
namespace {

class Ros2Sink : public FrameSink {
 public:
  explicit Ros2Sink(const ros2::Ros2Config& config) : publisher_(config) {}

  void wait_for(unsigned subscribers, double timeout_s) {
    const auto& c = publisher_.config();
    std::fprintf(stderr, "vlpground: ros2: waiting for %u subscriber(s) on %s (domain %u)\n",
                 subscribers, c.topic.c_str(), c.domain_id);
    if (!publisher_.wait_for_subscribers(subscribers,
                                         static_cast<int>(std::lround(timeout_s * 1000)))) {
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%g", timeout_s);
      throw std::runtime_error("no subscriber matched " + c.topic + " within " + seconds +
                               " s (--ros2-wait-timeout); a reliable subscriber does not match "
                               "--ros2-qos sensor-data");
    }
  }

  void write(const LabelledFrame& f) override { publisher_.publish(f.frame, f.ground); }

  void finish() override {
    const bool delivered = publisher_.finish(kFinishTimeoutMs);
    const auto s = publisher_.stats();
    std::fprintf(stderr,
                 "vlpground: ros2: %llu of %llu frames published on %s (%llu skipped while the publisher "
                 "was busy, %llu write errors, %u subscriber(s))%s\n",
                 static_cast<unsigned long long>(s.frames_published),
                 static_cast<unsigned long long>(s.frames_offered),
                 publisher_.config().topic.c_str(),
                 static_cast<unsigned long long>(s.frames_skipped),
                 static_cast<unsigned long long>(s.write_errors), s.matched_subscribers,
                 delivered ? "" : "; not every subscriber acknowledged the last frames");
  }

 private:
  static constexpr int kFinishTimeoutMs = 2000;
  ros2::Ros2Publisher publisher_;
};

}  // namespace

void add_ros2_options(CLI::App& cmd, Ros2Options& o) {
  const char* group = "ROS 2 output (DDS)";
  cmd.add_flag("--ros2", o.enabled,
               "publish every labelled frame as sensor_msgs/PointCloud2 (organized 16 x columns, "
               "32 rows in dual mode; fields x y z intensity ring time label return)")
      ->group(group);
  cmd.add_option("--ros2-topic", o.config.topic, "ROS 2 topic of the organized cloud")
      ->type_name("TOPIC")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--frame-id", o.config.frame_id, "header.frame_id of the clouds")
      ->type_name("ID")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--ros2-domain", o.config.domain_id,
                 "DDS domain = ROS_DOMAIN_ID (default: $ROS_DOMAIN_ID, else 0)")
      ->type_name("N")
      ->check(CLI::Range(0, 232))
      ->group(group);
  cmd.add_option("--ros2-qos", o.qos,
                 "reliable (RELIABLE, keep-last 10, like ros-drivers/velodyne) or sensor-data "
                 "(BEST_EFFORT, keep-last 5; reliable subscribers do not match it)")
      ->type_name("Q")
      ->check([](const std::string& text) {
        try {
          ros2::parse_qos_profile(text);
          return std::string();
        } catch (const std::invalid_argument& e) {
          return std::string(e.what());
        }
      })
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--ros2-ground-topic", o.config.ground_topic,
                 "also publish the returns labelled ground as a dense cloud on this topic")
      ->type_name("TOPIC")
      ->group(group);
  cmd.add_option("--ros2-obstacle-topic", o.config.obstacle_topic,
                 "also publish the returns labelled obstacle as a dense cloud on this topic")
      ->type_name("TOPIC")
      ->group(group);
  cmd.add_option("--ros2-wait-subscribers", o.wait_subscribers,
                 "before the first frame, wait until N subscribers matched the topic (replay "
                 "into a viewer without losing the first frames)")
      ->type_name("N")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--ros2-wait-timeout", o.wait_timeout_s,
                 "give up waiting for subscribers after this many seconds (exit status 1)")
      ->type_name("S")
      ->check(CLI::PositiveNumber)
      ->capture_default_str()
      ->group(group);
  if (const char* env = std::getenv("ROS_DOMAIN_ID"); env != nullptr && *env != '\0') {
    char* end = nullptr;
    const unsigned long domain = std::strtoul(env, &end, 10);
    if (*end == '\0' && domain <= 232) o.config.domain_id = static_cast<std::uint32_t>(domain);
  }
}

std::string describe_ros2_destination(const Ros2Options& o) {
  return o.config.topic + " (domain " + std::to_string(o.config.domain_id) + ")";
}

std::unique_ptr<FrameSink> make_ros2_sink(const Ros2Options& o, const PipelineConfig& config) {
  if (!o.enabled) return nullptr;
  ros2::Ros2Config c = o.config;
  c.qos = ros2::parse_qos_profile(o.qos);
  c.capacity_columns = config.assembler.capacity_columns;
  // Like the pipeline: a replay that blocks its reader loses no frame here either; a live
  // sensor never waits for a subscriber.
  const bool blocking = config.backpressure == Backpressure::block ||
                        (config.backpressure == Backpressure::automatic && config.pcap.has_value());
  c.when_busy = blocking ? ros2::WhenBusy::wait : ros2::WhenBusy::replace_waiting;
  auto sink = std::make_unique<Ros2Sink>(c);
  if (o.wait_subscribers > 0) sink->wait_for(o.wait_subscribers, o.wait_timeout_s);
  return sink;
}

#else

void add_ros2_options(CLI::App& cmd, Ros2Options& o) {
  cmd.add_flag("--ros2", o.enabled, "ROS 2 output (not built: VLPGROUND_WITH_ROS2 is off)")
      ->group("ROS 2 output (DDS)");
}

std::string describe_ros2_destination(const Ros2Options&) { return "(not built)"; }

std::unique_ptr<FrameSink> make_ros2_sink(const Ros2Options& o, const PipelineConfig&) {
  if (!o.enabled) return nullptr;
  throw std::runtime_error(
      "this vlpground was built without ROS 2 output; install cyclonedds-dev and "
      "cyclonedds-tools and configure with -DVLPGROUND_WITH_ROS2=ON");
}

#endif
}  // namespace vlpground::cli
