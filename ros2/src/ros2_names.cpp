// ROS 2 naming and QoS-name rules of the publisher's config (no DDS here).
#include <cctype>
#include <stdexcept>
#include <string>

#include "vlpground/ros2/publisher.hpp"

namespace vlpground::ros2 {
namespace {

// An absolute ROS 2 topic name: "/" then tokens of [A-Za-z0-9_] separated by single "/",
// no token starting with a digit, no trailing "/".
bool is_absolute_topic(const std::string& name) {
  if (name.size() < 2 || name.front() != '/' || name.back() == '/') return false;
  bool token_start = true;
  for (std::size_t i = 1; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (c == '/') {
      if (token_start) return false;  // "//"
      token_start = true;
      continue;
    }
    if (std::isalnum(c) == 0 && c != '_') return false;
    if (token_start && std::isdigit(c) != 0) return false;
    token_start = false;
  }
  return true;
}

void check_topic(const char* field, const std::string& name, bool optional) {
  if (optional && name.empty()) return;
  if (!is_absolute_topic(name)) {
    throw std::invalid_argument(std::string("ros2 ") + field + " must be an absolute ROS 2 name " +
                                "like /vlpground/points (letters, digits, '_', '/'), got '" +
                                name + "'");
  }
}

}  // namespace

void Ros2Config::validate() const {
  check_topic("topic", topic, false);
  check_topic("ground_topic", ground_topic, true);
  check_topic("obstacle_topic", obstacle_topic, true);
  if (ground_topic == topic || obstacle_topic == topic ||
      (!ground_topic.empty() && ground_topic == obstacle_topic)) {
    throw std::invalid_argument("ros2 topics must differ from each other");
  }
  if (frame_id.empty()) throw std::invalid_argument("ros2 frame_id must not be empty");
  if (domain_id > 232) {
    throw std::invalid_argument("ros2 domain_id must be 0..232, got " + std::to_string(domain_id));
  }
  if (capacity_columns < 1) throw std::invalid_argument("ros2 capacity_columns must be >= 1");
  if (reliable_block_ms < 0) throw std::invalid_argument("ros2 reliable_block_ms must be >= 0");
}

std::string dds_topic_name(const std::string& ros_topic) { return "rt" + ros_topic; }

QosProfile parse_qos_profile(const std::string& text) {
  if (text == "reliable") return QosProfile::reliable;
  if (text == "sensor-data") return QosProfile::sensor_data;
  throw std::invalid_argument("ros2 QoS must be reliable or sensor-data, got '" + text + "'");
}

}  // namespace vlpground::ros2
