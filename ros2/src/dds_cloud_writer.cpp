#include "dds_cloud_writer.hpp"

#include <dds/dds.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <stdexcept>
#include <string>

#include "PointCloud2.h"

namespace vlpground::ros2::detail {
namespace {

using Cloud = sensor_msgs_msg_dds__PointCloud2_;
using Field = sensor_msgs_msg_dds__PointField_;

// kPointFields as DDS PointField_ values; the names point at static storage.
std::array<Field, outputs::kPointFields.size()>& wire_fields() {
  static std::array<std::string, outputs::kPointFields.size()> names;
  static std::array<Field, outputs::kPointFields.size()> fields = [] {
    std::array<Field, outputs::kPointFields.size()> out{};
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto& spec = outputs::kPointFields[i];
      names[i] = std::string(spec.name);
      out[i].name = names[i].data();
      out[i].offset = spec.offset;
      out[i].datatype = static_cast<std::uint8_t>(spec.datatype);
      out[i].count = spec.count;
    }
    return out;
  }();
  return fields;
}

[[noreturn]] void fail(const std::string& what, dds_return_t rc) {
  throw std::runtime_error("ros2: " + what + ": " + dds_strretcode(rc));
}

dds_qos_t* make_qos(const Ros2Config& config) {
  dds_qos_t* qos = dds_create_qos();
  if (config.qos == QosProfile::reliable) {
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(config.reliable_block_ms));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  } else {
    dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 5);
  }
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  // Plain CDR, what ROS 2's RMW layers send and expect.
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos, 1, &xcdr1);
  return qos;
}

}  // namespace

DdsCloudWriters::DdsCloudWriters(const Ros2Config& config) : frame_id_(config.frame_id) {
  participant_ = dds_create_participant(config.domain_id, nullptr, nullptr);
  if (participant_ < 0) {
    fail("cannot join DDS domain " + std::to_string(config.domain_id), participant_);
  }
  const std::string* topics[3] = {&config.topic, &config.ground_topic, &config.obstacle_topic};
  dds_qos_t* qos = make_qos(config);
  for (std::size_t t = 0; t < 3; ++t) {
    if (topics[t]->empty()) continue;
    const std::string name = dds_topic_name(*topics[t]);
    const dds_entity_t topic = dds_create_topic(participant_, &sensor_msgs_msg_dds__PointCloud2__desc,
                                                name.c_str(), nullptr, nullptr);
    if (topic < 0) {
      dds_delete_qos(qos);
      dds_delete(participant_);
      fail("cannot create topic " + name, topic);
    }
    writer_[t] = dds_create_writer(participant_, topic, qos, nullptr);
    if (writer_[t] < 0) {
      const dds_return_t rc = writer_[t];
      dds_delete_qos(qos);
      dds_delete(participant_);
      fail("cannot create a writer for " + name, rc);
    }
  }
  dds_delete_qos(qos);
  dds_set_status_mask(writer_[0], DDS_PUBLICATION_MATCHED_STATUS);
  waitset_ = dds_create_waitset(participant_);
  dds_waitset_attach(waitset_, writer_[0], 0);
}

DdsCloudWriters::~DdsCloudWriters() { dds_delete(participant_); }

WriteResult DdsCloudWriters::write(std::size_t topic, std::int64_t stamp_ns,
                                   const outputs::CloudShape& shape,
                                   std::span<std::uint8_t> data) {
  auto& fields = wire_fields();
  Cloud sample{};
  // Floor division: stamps before 1970 keep nanosec in [0, 1e9).
  std::int64_t sec = stamp_ns / 1'000'000'000;
  std::int64_t nsec = stamp_ns % 1'000'000'000;
  if (nsec < 0) {
    nsec += 1'000'000'000;
    --sec;
  }
  sample.header.stamp.sec = static_cast<std::int32_t>(sec);
  sample.header.stamp.nanosec = static_cast<std::uint32_t>(nsec);
  sample.header.frame_id = frame_id_.data();
  sample.height = shape.height;
  sample.width = shape.width;
  sample.fields._maximum = sample.fields._length = static_cast<std::uint32_t>(fields.size());
  sample.fields._buffer = fields.data();
  sample.fields._release = false;
  sample.is_bigendian = outputs::kBigEndian;
  sample.point_step = shape.point_step;
  sample.row_step = shape.row_step;
  sample.data._maximum = sample.data._length = static_cast<std::uint32_t>(shape.bytes());
  sample.data._buffer = data.data();
  sample.data._release = false;
  sample.is_dense = shape.is_dense;
  return dds_write(writer_[topic], &sample) == DDS_RETCODE_OK ? WriteResult::ok
                                                               : WriteResult::failed;
}

std::uint32_t DdsCloudWriters::matched() const {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(writer_[0], &status) != DDS_RETCODE_OK) return 0;
  return status.current_count;
}

bool DdsCloudWriters::wait_matched(std::uint32_t count, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (matched() < count) {
    const auto left = deadline - std::chrono::steady_clock::now();
    if (left <= std::chrono::nanoseconds::zero()) return false;
    // At most 50 ms per round: another thread reading the status (stats()) clears the
    // trigger this waitset waits on.
    const auto slice = std::min<std::chrono::nanoseconds>(left, std::chrono::milliseconds(50));
    dds_waitset_wait(waitset_, nullptr, 0, slice.count());
  }
  return true;
}

bool DdsCloudWriters::wait_for_acks(int timeout_ms) {
  const dds_time_t deadline = dds_time() + DDS_MSECS(timeout_ms);
  bool all = true;
  for (const dds_entity_t w : writer_) {
    if (w <= 0) continue;
    const dds_duration_t left = std::max<dds_duration_t>(0, deadline - dds_time());
    if (dds_wait_for_acks(w, left) != DDS_RETCODE_OK) all = false;
  }
  return all;
}

}  // namespace vlpground::ros2::detail
