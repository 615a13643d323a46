// A PacketSource over packets held in memory (no I/O), for CaptureReader tests and benches.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vlpground/driver/packet_source.hpp"

namespace vlpground::test {

class MemorySource final : public PacketSource {
 public:
  struct Packet {
    std::vector<std::uint8_t> bytes;
    PacketKind kind = PacketKind::data;
    std::int64_t receive_ns = 0;
  };

  explicit MemorySource(std::vector<Packet> packets) : packets_(std::move(packets)) {}

  SourceStatus next(PacketView& out, int /*timeout_ms*/) override {
    if (stop_) return SourceStatus::stopped;
    if (at_ >= packets_.size()) return SourceStatus::end_of_file;
    const Packet& p = packets_[at_++];
    ++counters_.records;
    ++(p.kind == PacketKind::data ? counters_.data_packets : counters_.position_packets);
    out.bytes = p.bytes;
    out.kind = p.kind;
    out.receive_ns = p.receive_ns;
    out.steady_receive_ns = static_cast<std::int64_t>(at_);
    return SourceStatus::packet;
  }
  void request_stop() override { stop_ = true; }
  [[nodiscard]] const SourceCounters& counters() const override { return counters_; }
  [[nodiscard]] bool is_live() const override { return false; }
  [[nodiscard]] std::string describe() const override { return "memory"; }
  /// Starts over (for benchmarks replaying the same packets).
  void rewind() { at_ = 0; }

 private:
  std::vector<Packet> packets_;
  std::size_t at_ = 0;
  SourceCounters counters_;
  bool stop_ = false;
};

}  // namespace vlpground::test
