// Assembles decoded firing columns into complete rotations (16 x N range images), cutting
// at a configured azimuth at the firing, never at the packet.
//
// Thread-safety: one RotationAssembler per thread.
#pragma once

#include <cstdint>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/frame.hpp"

namespace vlpground {

struct AssemblerConfig {
  double cut_angle_deg = 0.0;       // frames start at the first firing at/after this azimuth
  double silence_timeout_ms = 200;  // a longer gap ends the frame in progress (incomplete)
  int capacity_columns = kDefaultFrameCapacity;

  /// Throws std::invalid_argument with a clear message.
  void validate() const;
};

struct AssemblerCounters {
  std::uint64_t frames = 0;
  std::uint64_t incomplete_frames = 0;
  std::uint64_t packets_used = 0;
  std::uint64_t packets_lost = 0;        // inferred from timestamp gaps
  std::uint64_t duplicate_packets = 0;   // same timestamp as one already used
  std::uint64_t reordered_packets = 0;   // older than the newest used (dropped, counted)
  std::uint64_t columns_lost = 0;
};

class RotationAssembler {
 public:
  explicit RotationAssembler(const AssemblerConfig& config = {});

  /// Adds one decoded packet. When this completes a frame, swaps it into `out` (whose old
  /// storage becomes the next frame in progress) and returns true. Never allocates as long
  /// as `out` has the configured capacity.
  bool push(const DecodedPacket& packet, Frame& out);

  /// Emits the frame in progress, marked incomplete, if it holds any column (end of file,
  /// long silence). Returns false when there was nothing to emit.
  bool flush(Frame& out);

  /// Counts a packet skipped upstream (malformed, filtered) against the frame in progress.
  void note_skipped_packet();

  [[nodiscard]] const AssemblerCounters& counters() const { return counters_; }

 private:
  AssemblerConfig config_;
  AssemblerCounters counters_;
  Frame current_;
};

}  // namespace vlpground
