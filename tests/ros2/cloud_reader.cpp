#include "cloud_reader.hpp"

#include <dds/dds.h>

#include <chrono>
#include <stdexcept>

#include "PointCloud2.h"

namespace vlpground::test {
namespace {

void check(dds_return_t rc, const char* what) {
  if (rc < 0) throw std::runtime_error(std::string(what) + ": " + dds_strretcode(rc));
}

std::int64_t ns_left(std::chrono::steady_clock::time_point deadline) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(deadline -
                                                              std::chrono::steady_clock::now())
      .count();
}

}  // namespace

CloudReader::CloudReader(std::uint32_t domain, const std::string& dds_topic, ReaderQos qos,
                         int max_samples) {
  participant_ = dds_create_participant(domain, nullptr, nullptr);
  check(participant_, "participant");
  const dds_entity_t topic = dds_create_topic(participant_, &sensor_msgs_msg_dds__PointCloud2__desc,
                                              dds_topic.c_str(), nullptr, nullptr);
  check(topic, "topic");
  dds_qos_t* q = dds_create_qos();
  if (qos == ReaderQos::reliable) {
    dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  } else {
    dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
  }
  dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
  if (max_samples > 0) {
    dds_qset_resource_limits(q, max_samples, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  }
  reader_ = dds_create_reader(participant_, topic, q, nullptr);
  dds_delete_qos(q);
  check(reader_, "reader");
  waitset_ = dds_create_waitset(participant_);
  check(waitset_, "waitset");
  check(dds_waitset_attach(waitset_, reader_, 0), "attach");
}

CloudReader::~CloudReader() { dds_delete(participant_); }

bool CloudReader::wait_status(std::uint32_t status, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  check(dds_set_status_mask(reader_, status), "status mask");
  for (;;) {
    std::uint32_t got = 0;
    check(dds_read_status(reader_, &got, status), "read status");
    if (got != 0) return true;
    const std::int64_t left = ns_left(deadline);
    if (left <= 0) return false;
    dds_waitset_wait(waitset_, nullptr, 0, left);
  }
}

bool CloudReader::wait_matched(int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    dds_subscription_matched_status_t st{};
    check(dds_get_subscription_matched_status(reader_, &st), "matched status");
    if (st.current_count > 0) return true;
    if (ns_left(deadline) <= 0) return false;
    wait_status(DDS_SUBSCRIPTION_MATCHED_STATUS,
                static_cast<int>(std::min<std::int64_t>(50, ns_left(deadline) / 1'000'000 + 1)));
  }
}

bool CloudReader::wait_incompatible_qos(int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    dds_requested_incompatible_qos_status_t st{};
    check(dds_get_requested_incompatible_qos_status(reader_, &st), "incompatible status");
    if (st.total_count > 0) return true;
    if (ns_left(deadline) <= 0) return false;
    wait_status(DDS_REQUESTED_INCOMPATIBLE_QOS_STATUS,
                static_cast<int>(std::min<std::int64_t>(50, ns_left(deadline) / 1'000'000 + 1)));
  }
}

bool CloudReader::take(ReceivedCloud& out, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  check(dds_set_status_mask(reader_, DDS_DATA_AVAILABLE_STATUS), "status mask");
  for (;;) {
    void* samples[1] = {nullptr};
    dds_sample_info_t info[1];
    const dds_return_t n = dds_take(reader_, samples, info, 1, 1);
    check(n, "take");
    if (n > 0 && info[0].valid_data) {
      const auto* s = static_cast<const sensor_msgs_msg_dds__PointCloud2_*>(samples[0]);
      out.sec = s->header.stamp.sec;
      out.nanosec = s->header.stamp.nanosec;
      out.frame_id = s->header.frame_id;
      out.height = s->height;
      out.width = s->width;
      out.point_step = s->point_step;
      out.row_step = s->row_step;
      out.is_bigendian = s->is_bigendian;
      out.is_dense = s->is_dense;
      out.fields.clear();
      for (std::uint32_t i = 0; i < s->fields._length; ++i) {
        const auto& f = s->fields._buffer[i];
        out.fields.push_back({f.name, f.offset, f.datatype, f.count});
      }
      out.data.assign(s->data._buffer, s->data._buffer + s->data._length);
      dds_return_loan(reader_, samples, n);
      return true;
    }
    if (n > 0) dds_return_loan(reader_, samples, n);
    const std::int64_t left = ns_left(deadline);
    if (left <= 0) return false;
    dds_waitset_wait(waitset_, nullptr, 0, left);
  }
}

}  // namespace vlpground::test
