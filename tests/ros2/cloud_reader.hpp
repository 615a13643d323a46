// A PointCloud2 subscriber for the tests, written against the IDL's generated types and the
// plain Cyclone DDS C API only (independent of the publisher library): it joins a DDS topic
// by its ROS 2 name and type name and copies each sample out.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vlpground::test {

struct ReceivedField {
  std::string name;
  std::uint32_t offset;
  std::uint8_t datatype;
  std::uint32_t count;
};

struct ReceivedCloud {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  std::string frame_id;
  std::uint32_t height = 0, width = 0, point_step = 0, row_step = 0;
  bool is_bigendian = false, is_dense = false;
  std::vector<ReceivedField> fields;
  std::vector<std::uint8_t> data;
};

enum class ReaderQos : std::uint8_t { reliable, best_effort };

class CloudReader {
 public:
  /// Joins `domain` and reads DDS topic `dds_topic` (e.g. "rt/vlpground/points") with type
  /// sensor_msgs::msg::dds_::PointCloud2_, keeping every sample it has not taken, or at most
  /// `max_samples` (> 0: a reader that stops taking stalls a reliable writer). Throws
  /// std::runtime_error.
  CloudReader(std::uint32_t domain, const std::string& dds_topic, ReaderQos qos,
              int max_samples = 0);
  ~CloudReader();
  CloudReader(const CloudReader&) = delete;
  CloudReader& operator=(const CloudReader&) = delete;

  /// Takes the next sample into `out`; false when none arrived within `timeout_ms`.
  bool take(ReceivedCloud& out, int timeout_ms);
  /// True once a writer matched (within `timeout_ms`).
  bool wait_matched(int timeout_ms);
  /// True once a writer was refused for incompatible QoS (within `timeout_ms`).
  bool wait_incompatible_qos(int timeout_ms);

 private:
  bool wait_status(std::uint32_t status, int timeout_ms);
  std::int32_t participant_ = 0, reader_ = 0, waitset_ = 0;
};

}  // namespace vlpground::test
