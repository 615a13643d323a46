// Publishes labelled frames as ROS 2 sensor_msgs/PointCloud2 over DDS (Eclipse Cyclone DDS),
// without a ROS 2 installation: ROS 2 nodes, rviz2 and `ros2 topic echo` receive them.
// docs/ros2.md lists the wire facts (DDS topic and type names, point layout, QoS).
//
// publish() is meant for the frame callback: it encodes the frame into a preallocated slot
// and returns; a publisher thread hands the newest encoded frame to DDS. A slow or absent
// subscriber never blocks the caller: when the thread is still busy with an earlier frame,
// a newer one replaces the frame waiting to be sent (counted in Ros2Stats::frames_skipped).
// Replays that must not lose a frame choose WhenBusy::wait instead. No heap allocation per
// frame once the slots have grown to the frame size.
//
// The DDS network configuration is Cyclone DDS's own: the CYCLONEDDS_URI environment
// variable (interfaces, multicast, peers); without it Cyclone's defaults apply.
//
// The threads it starts (Cyclone DDS's and its own) block asynchronous signals (SIGINT,
// SIGTERM, ...), whatever the creating thread's mask.
//
// Thread-safety: publish() from one thread at a time; stats(), wait_for_subscribers() and
// finish() from any thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::ros2 {

enum class QosProfile : std::uint8_t {
  reliable,     // RELIABLE, keep-last 10 (as ros-drivers/velodyne publishes its cloud)
  sensor_data,  // BEST_EFFORT, keep-last 5 (rclcpp::SensorDataQoS)
};

/// What publish() does when the previous frame is still waiting for the publisher thread.
enum class WhenBusy : std::uint8_t {
  replace_waiting,  // never wait: the newer frame replaces it (live sensors)
  wait,             // wait until the thread took it: no frame lost (replay as fast as possible)
};

struct Ros2Config {
  std::string topic = "/vlpground/points";  // organized cloud (ROS 2 name)
  std::string ground_topic;                 // dense ground-only cloud; empty = not published
  std::string obstacle_topic;               // dense obstacle-only cloud; empty = not published
  std::string frame_id = "velodyne";        // header.frame_id
  std::uint32_t domain_id = 0;              // ROS_DOMAIN_ID
  QosProfile qos = QosProfile::reliable;
  WhenBusy when_busy = WhenBusy::replace_waiting;
  int capacity_columns = kDefaultFrameCapacity;  // slots are sized for frames this wide
  int reliable_block_ms = 100;  // reliable only: how long the publisher thread may wait for a
                                // full writer history before that frame is given up

  /// Throws std::invalid_argument naming the bad field (topics must be absolute ROS 2 names,
  /// domain 0..232, frame_id non-empty).
  void validate() const;
};

struct Ros2Stats {
  std::uint64_t frames_offered = 0;    // publish() calls
  std::uint64_t frames_published = 0;  // written to DDS (every configured topic)
  std::uint64_t frames_skipped = 0;    // replaced by a newer frame while the thread was busy
  std::uint64_t write_errors = 0;      // DDS refused or timed out a write (reliable, slow reader)
  std::uint32_t matched_subscribers = 0;  // readers matched on the main topic now
};

/// The DDS topic of a ROS 2 topic name: "/vlpground/points" -> "rt/vlpground/points".
std::string dds_topic_name(const std::string& ros_topic);

/// Accepts "reliable" and "sensor-data"; throws std::invalid_argument otherwise.
QosProfile parse_qos_profile(const std::string& text);

class Ros2Publisher {
 public:
  /// Validates `config`, joins the DDS domain, creates the writers and starts the publisher
  /// thread. Throws std::invalid_argument (config) or std::runtime_error (DDS, with reason).
  explicit Ros2Publisher(const Ros2Config& config);
  /// finish(), then leaves the domain.
  ~Ros2Publisher();
  Ros2Publisher(const Ros2Publisher&) = delete;
  Ros2Publisher& operator=(const Ros2Publisher&) = delete;

  /// Encodes the frame for sending and returns without waiting for DDS. Header stamp =
  /// FrameMeta::first_time_ns. Frames wider than `capacity_columns` grow the slots once.
  void publish(const Frame& frame, const GroundResult& ground);

  /// Waits until at least `count` readers matched the main topic; false on timeout.
  bool wait_for_subscribers(std::uint32_t count, int timeout_ms);

  /// Sends the frame still waiting (if any), then waits until reliable readers acknowledged
  /// everything written, at most `timeout_ms`; false on timeout. publish() after finish() is
  /// an error (std::logic_error).
  bool finish(int timeout_ms = 2000);

  [[nodiscard]] Ros2Stats stats() const;
  [[nodiscard]] const Ros2Config& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground::ros2
