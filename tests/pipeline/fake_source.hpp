// A synthetic PacketSource for pipeline tests: a VLP-16 spinning at 600 rpm over a flat floor,
// encoded with the simulator's packet encoder. Live or replay, fully deterministic, and it
// allocates nothing in next().
#pragma once

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "vlpground/driver/packet_source.hpp"
#include "vlpground/sim/packet_encoder.hpp"

namespace vlpground::test {

class FakeSource final : public PacketSource {
 public:
  static constexpr int kPacketsPerRotation = 76;  // ~75.4 at 600 rpm

  FakeSource(int packets, bool live) : live_(live) {
    packets_.resize(static_cast<std::size_t>(packets));
    constexpr std::int64_t kPeriodNs = 1'327'104;
    constexpr double kDegPerNs = 360.0 / 100e6;  // 600 rpm
    for (int k = 0; k < packets; ++k) {
      sim::DataPacketFields f;
      const std::int64_t t0 = k * kPeriodNs;
      for (int b = 0; b < 12; ++b) {
        const double az = std::fmod(static_cast<double>(t0 + 2 * b * 55'296) * kDegPerNs, 360.0);
        f.azimuth_centideg[static_cast<std::size_t>(b)] =
            static_cast<std::uint16_t>(std::lround(az * 100.0) % 36000);
        for (int ch = 0; ch < 32; ++ch) {
          const int laser = ch % 16;
          // Even lasers look down (ground at 1.8 m below), odd ones up (a 20 m wall).
          const double elev = (laser % 2 == 0) ? (-15.0 + laser) : static_cast<double>(laser);
          const double range = elev < 0 ? 1.8 / std::sin(-elev * std::numbers::pi / 180) : 20.0;
          f.distance_2mm[static_cast<std::size_t>(b)][static_cast<std::size_t>(ch)] =
              static_cast<std::uint16_t>(std::lround(range / 0.002));
          f.reflectivity[static_cast<std::size_t>(b)][static_cast<std::size_t>(ch)] = 40;
        }
      }
      f.stamp_us_past_hour = static_cast<std::uint32_t>(1'000'000 + t0 / 1000);
      sim::encode_data_packet(f,
                              std::span<std::uint8_t, 1206>(packets_[static_cast<std::size_t>(k)]));
    }
  }

  /// Calls `hold` (which may block) once, before serving packet `index`: lets a test order
  /// the reader thread after an event of the detector thread without sleeping.
  void hold_before(std::size_t index, std::function<void()> hold) {
    hold_index_ = index;
    hold_ = std::move(hold);
  }

  SourceStatus next(PacketView& out, int /*timeout_ms*/) override {
    if (stop_) return SourceStatus::stopped;
    if (hold_ && index_ == hold_index_) std::exchange(hold_, nullptr)();
    if (index_ >= packets_.size()) return SourceStatus::end_of_file;
    const auto& p = packets_[index_];
    out.bytes = std::span<const std::uint8_t>(p.data(), p.size());
    out.kind = PacketKind::data;
    // 2023-11-14 22:00:00 UTC + stamp.
    out.receive_ns =
        1'699'999'200'000'000'000 + 1'000'000'000 + static_cast<std::int64_t>(index_) * 1'327'104;
    out.steady_receive_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                std::chrono::steady_clock::now().time_since_epoch())
                                .count();
    ++index_;
    ++counters_.records;
    ++counters_.data_packets;
    served_.store(index_);
    return SourceStatus::packet;
  }
  void request_stop() override { stop_ = true; }
  [[nodiscard]] const SourceCounters& counters() const override { return counters_; }
  [[nodiscard]] bool is_live() const override { return live_; }
  [[nodiscard]] double progress() const override {
    return live_ ? -1.0 : static_cast<double>(index_) / static_cast<double>(packets_.size());
  }
  [[nodiscard]] std::string describe() const override { return "fake"; }

  /// Packets handed out so far (any thread).
  [[nodiscard]] std::size_t served() const { return served_.load(); }

 private:
  std::vector<std::array<std::uint8_t, 1206>> packets_;
  std::size_t index_ = 0;
  std::atomic<std::size_t> served_{0};
  std::atomic<bool> stop_{false};
  SourceCounters counters_;
  bool live_;
  std::size_t hold_index_ = 0;
  std::function<void()> hold_;
};

}  // namespace vlpground::test
