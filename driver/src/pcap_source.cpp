// Replay of pcap / pcapng captures through libpcap, optionally paced and looped.
#include <pcap/pcap.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>

#include "frame_parser.hpp"
#include "loop_seam.hpp"
#include "packet_filter.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/error.hpp"

namespace vlpground {

void PcapSourceConfig::validate() const {
  if (path.empty()) throw std::invalid_argument("pcap source: path is empty");
  if (data_port == 0) throw std::invalid_argument("pcap source: data_port must not be 0");
  if (!std::isfinite(rate) || rate < 0.0) {
    throw std::invalid_argument("pcap source: rate must be >= 0 (0 = as fast as possible), got " +
                                std::to_string(rate));
  }
  (void)driver_detail::parse_sensor_address(sensor_address);
}

namespace {

using Clock = std::chrono::steady_clock;
using driver_detail::FrameKind;

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
      .count();
}

struct PcapCloser {
  void operator()(pcap_t* handle) const { pcap_close(handle); }
};
using PcapHandle = std::unique_ptr<pcap_t, PcapCloser>;

PcapHandle open_capture(const std::string& path) {
  char errbuf[PCAP_ERRBUF_SIZE] = {};
  pcap_t* handle =
      pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, errbuf);
  if (handle == nullptr) {
    throw Error(ErrorCode::cannot_open_file, "cannot open capture '" + path + "': " + errbuf);
  }
  PcapHandle owned(handle);
  const int link_type = pcap_datalink(handle);
  if (!driver_detail::is_supported_link_type(link_type)) {
    const char* name = pcap_datalink_val_to_name(link_type);
    throw Error(ErrorCode::unsupported_link_type, "capture '" + path + "' has unsupported link type " +
                             std::to_string(link_type) + " (" + (name ? name : "unknown") + ")");
  }
  return owned;
}

/// Thread-safety: one thread calls next(); request_stop() from any thread.
class PcapSource final : public PacketSource {
 public:
  explicit PcapSource(const PcapSourceConfig& config)
      : config_(config), handle_(open_capture(config.path)) {
    filter_.data_port = config.data_port;
    filter_.position_port = config.position_port;
    filter_.sensor = driver_detail::parse_sensor_address(config.sensor_address);
    link_type_ = pcap_datalink(handle_.get());
    std::error_code ec;
    const auto size = std::filesystem::file_size(config.path, ec);
    file_bytes_ = ec ? 0 : static_cast<double>(size);
  }

  SourceStatus next(PacketView& out, int timeout_ms) override {
    if (stop_.load(std::memory_order_acquire)) return SourceStatus::stopped;
    if (!has_pending_) {
      const SourceStatus status = read_next_packet();
      if (status != SourceStatus::packet) return status;
    }
    if (config_.rate > 0.0) {
      const SourceStatus status = wait_for_pacing(timeout_ms);
      if (status != SourceStatus::packet) return status;
    }
    has_pending_ = false;
    out = pending_;
    out.steady_receive_ns = steady_now_ns();
    return SourceStatus::packet;
  }

  void request_stop() override {
    {
      std::lock_guard lock(stop_mutex_);
      stop_.store(true, std::memory_order_release);
    }
    stop_cv_.notify_all();
  }

  [[nodiscard]] const SourceCounters& counters() const override { return counters_; }
  [[nodiscard]] bool is_live() const override { return false; }

  [[nodiscard]] double progress() const override {
    if (at_end_) return 1.0;
    if (!handle_ || file_bytes_ <= 0.0) return 0.0;
    FILE* file = pcap_file(handle_.get());
    const long position = file ? std::ftell(file) : -1L;
    if (position < 0) return 0.0;
    return std::min(1.0, static_cast<double>(position) / file_bytes_);
  }

  [[nodiscard]] std::string describe() const override { return "pcap " + config_.path; }

 private:
  // Reads records until one is a packet for us (left in pending_), or the input ends.
  SourceStatus read_next_packet() {
    for (;;) {
      if (at_end_) return SourceStatus::end_of_file;
      pcap_pkthdr* header = nullptr;
      const std::uint8_t* data = nullptr;
      const int result = pcap_next_ex(handle_.get(), &header, &data);
      if (result != 1) {
        // -1 here is a record cut short by the end of the file: counted, never fatal.
        if (result == PCAP_ERROR) {
          ++counters_.records;
          ++counters_.truncated;
        }
        if (!restart_for_loop()) {
          at_end_ = true;
          return SourceStatus::end_of_file;
        }
        continue;
      }
      if (classify(*header, data)) return SourceStatus::packet;
    }
  }

  bool classify(const pcap_pkthdr& header, const std::uint8_t* data) {
    ++counters_.records;
    const std::int64_t stamp_ns = static_cast<std::int64_t>(header.ts.tv_sec) * 1'000'000'000 +
                                  static_cast<std::int64_t>(header.ts.tv_usec);  // nano precision
    note_stamp(stamp_ns);
    if (header.caplen < header.len) {
      ++counters_.truncated;
      return false;
    }
    driver_detail::UdpDatagram datagram;
    switch (driver_detail::parse_frame(link_type_, {data, header.caplen}, datagram)) {
      case FrameKind::udp:
        break;
      case FrameKind::fragment:
        ++counters_.skipped_fragment;
        return false;
      case FrameKind::truncated:
        ++counters_.truncated;
        return false;
      case FrameKind::other:
        ++counters_.skipped_other;
        return false;
    }
    const auto kind = filter_.accept(datagram, counters_);
    if (!kind) return false;
    if (config_.loop && !continues_rotation(*kind, datagram.payload, stamp_ns)) return false;
    ++packets_this_pass_;
    pending_.bytes = datagram.payload;
    pending_.kind = *kind;
    pending_.source = driver_detail::to_source_address(datagram);
    pending_.receive_ns = stamp_ns + seam_.receive_shift_ns();
    pending_.stamp_offset_ns = seam_.stamp_shift_ns();
    has_pending_ = true;
    return true;
  }

  // Looping: at the start of a later pass, packets before the one that continues the
  // rotation are skipped (counted; see loop_seam.hpp). False for a skipped packet.
  bool continues_rotation(PacketKind kind, std::span<const std::uint8_t> payload,
                          std::int64_t stamp_ns) {
    if (seam_.joining() && (kind != PacketKind::data || !seam_.join_at(payload, stamp_ns))) {
      --(kind == PacketKind::data ? counters_.data_packets : counters_.position_packets);
      ++counters_.skipped_loop;
      return false;
    }
    if (kind == PacketKind::data) seam_.note_data(payload, stamp_ns);
    return true;
  }

  void note_stamp(std::int64_t stamp_ns) {
    if (records_this_pass_ == 0) first_stamp_ns_ = stamp_ns;
    last_stamp_ns_ = stamp_ns;
    ++records_this_pass_;
  }

  // Looping: the next pass continues this one (loop_seam.hpp).
  bool restart_for_loop() {
    if (!config_.loop || packets_this_pass_ == 0) return false;
    seam_.end_pass(first_stamp_ns_, last_stamp_ns_, records_this_pass_);
    handle_.reset();
    handle_ = open_capture(config_.path);
    records_this_pass_ = 0;
    packets_this_pass_ = 0;
    ++counters_.loop_wraps;
    return true;
  }

  // Paces pending_ by its capture stamp: rate 1.0 = real time. Returns `packet` once due.
  SourceStatus wait_for_pacing(int timeout_ms) {
    const std::int64_t stamp_ns = pending_.receive_ns;
    if (!pacing_anchored_) {
      pacing_anchored_ = true;
      anchor_steady_ = Clock::now();
      anchor_stamp_ns_ = stamp_ns;
    }
    const auto offset = std::chrono::nanoseconds(
        static_cast<std::int64_t>(static_cast<double>(stamp_ns - anchor_stamp_ns_) / config_.rate));
    const Clock::time_point due = anchor_steady_ + offset;
    Clock::time_point wake = due;
    if (timeout_ms >= 0) wake = std::min(due, Clock::now() + std::chrono::milliseconds(timeout_ms));
    std::unique_lock lock(stop_mutex_);
    // Condition variable, not sleep_until, so request_stop() ends the wait at once.
    stop_cv_.wait_until(lock, wake, [this] { return stop_.load(std::memory_order_acquire); });
    if (stop_.load(std::memory_order_acquire)) return SourceStatus::stopped;
    return Clock::now() >= due ? SourceStatus::packet : SourceStatus::timeout;
  }

  PcapSourceConfig config_;
  PcapHandle handle_;
  driver_detail::PacketFilter filter_;
  int link_type_ = 0;
  double file_bytes_ = 0.0;
  SourceCounters counters_;

  PacketView pending_;
  bool has_pending_ = false;
  bool at_end_ = false;

  std::uint64_t records_this_pass_ = 0;
  std::uint64_t packets_this_pass_ = 0;
  std::int64_t first_stamp_ns_ = 0;
  std::int64_t last_stamp_ns_ = 0;
  driver_detail::LoopSeam seam_;

  bool pacing_anchored_ = false;
  Clock::time_point anchor_steady_;
  std::int64_t anchor_stamp_ns_ = 0;

  std::atomic<bool> stop_{false};
  std::mutex stop_mutex_;
  std::condition_variable stop_cv_;
};

}  // namespace

std::unique_ptr<PacketSource> open_pcap_source(const PcapSourceConfig& config) {
  config.validate();
  return std::make_unique<PcapSource>(config);
}

}  // namespace vlpground
