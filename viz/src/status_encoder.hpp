// /vlpground/status: pipeline counters, frame rate, detect time, latency and GPS/PPS state
// as one JSON object (schema: kStatusJsonSchema, documented in docs/foxglove.md).
#pragma once

#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "vlpground/driver/position_packet.hpp"
#include "vlpground/pipeline.hpp"

namespace vlpground::viz::detail {

extern const char* const kStatusJsonSchema;

class StatusEncoder {
 public:
  std::span<const std::byte> encode(const PipelineStats& stats);
  /// May be called from any thread.
  void note_position(const PositionPacket& packet);

 private:
  std::mutex position_mutex_;
  PositionPacket position_{};
  bool have_position_ = false;
  std::uint64_t last_delivered_ = 0;
  double last_elapsed_s_ = 0.0;
  std::string text_;
};

}  // namespace vlpground::viz::detail
