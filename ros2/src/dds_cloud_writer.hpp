// The DDS side of the publisher: one participant, a PointCloud2 writer per topic, and the
// reusable sample whose data sequence points at the caller's bytes (never copied or freed
// by us). Internal: the only place that sees Cyclone DDS types besides dds_cloud_writer.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "vlpground/outputs/pointcloud2.hpp"
#include "vlpground/ros2/publisher.hpp"

namespace vlpground::ros2::detail {

/// Result of one write.
enum class WriteResult : std::uint8_t { ok, failed };

class DdsCloudWriters {
 public:
  /// Throws std::runtime_error with Cyclone's reason when the domain or a writer fails.
  explicit DdsCloudWriters(const Ros2Config& config);
  ~DdsCloudWriters();
  DdsCloudWriters(const DdsCloudWriters&) = delete;
  DdsCloudWriters& operator=(const DdsCloudWriters&) = delete;

  /// Topic 0 = the organized cloud, 1 = ground-only, 2 = obstacle-only.
  [[nodiscard]] bool has_topic(std::size_t topic) const { return writer_[topic] > 0; }

  WriteResult write(std::size_t topic, std::int64_t stamp_ns, const outputs::CloudShape& shape,
                    std::span<std::uint8_t> data);

  /// Readers matched on topic 0 now.
  [[nodiscard]] std::uint32_t matched() const;
  /// Waits until topic 0 has `count` matched readers; false on timeout.
  bool wait_matched(std::uint32_t count, int timeout_ms);
  /// Waits for every reliable reader to acknowledge all writes; false on timeout.
  bool wait_for_acks(int timeout_ms);

 private:
  std::int32_t participant_ = 0;
  std::int32_t writer_[3] = {0, 0, 0};
  std::int32_t waitset_ = 0;
  std::string frame_id_;
};

}  // namespace vlpground::ros2::detail
