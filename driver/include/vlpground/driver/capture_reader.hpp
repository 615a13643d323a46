// Synchronous source -> decoder -> assembler chain in the caller's thread: the building block
// of the pipeline's acquisition thread, and the simple way for tools, tests and benchmarks to
// read frames from a capture or socket.
//
// Thread-safety: one thread drives a CaptureReader; request_stop() may be called from any.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <system_error>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/driver/position_packet.hpp"
#include "vlpground/driver/rotation_assembler.hpp"
#include "vlpground/frame.hpp"

namespace vlpground {

enum class ReadStatus : std::uint8_t { frame, timeout, end_of_input, stopped };

struct CaptureCounters {
  SourceCounters source;
  DecoderCounters decoder;
  AssemblerCounters assembler;
  std::uint64_t position_packets_parsed = 0;
};

class CaptureReader {
 public:
  CaptureReader(std::unique_ptr<PacketSource> source, const DecoderConfig& decoder = {},
                const AssemblerConfig& assembler = {});
  ~CaptureReader();

  /// Reads packets until a frame completes (returned in `out`, which must have the
  /// assembler's capacity), the input ends (the partial frame is flushed first, marked
  /// incomplete), `timeout_ms` passes without packets, or stop is requested.
  ReadStatus next(Frame& out, int timeout_ms = 1000);

  void request_stop();

  /// Called for every position packet (from the thread calling next()).
  void on_position(std::function<void(const PositionPacket&)> callback);
  /// Called once per distinct warning (product byte mismatch, not a VLP-16, ...) with its
  /// code (vlpground::ErrorCode) and message.
  void on_warning(std::function<void(std::error_code, const std::string&)> callback);

  [[nodiscard]] CaptureCounters counters() const;
  [[nodiscard]] const PacketSource& source() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground
