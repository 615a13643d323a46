// A PacketSource fed by the program: packets that arrive through other middleware (a
// recorded bag, another process, a shared-memory ring) are push()ed in and read by a
// pipeline or a CaptureReader like packets from a socket.
//
// Bounded: `capacity_packets` slots of 1206 bytes are allocated once; push() copies the
// payload into a free slot (no allocation per packet). When every slot is taken, push()
// either refuses the packet (counted in SourceCounters::queue_full, the live behaviour) or
// waits for room (`block_when_full`, for replay where nothing may be lost).
//
// Thread-safety: push(), close(), request_stop() and queue_full_count() from any thread,
// concurrently; next(), counters() from the one reading thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "vlpground/driver/packet_source.hpp"

namespace vlpground {

struct PushSourceConfig {
  int capacity_packets = 1024;  // ~1.4 s of single-return data at 754 packets/s
  /// false: push() refuses packets when full (counted; is_live() = true, so the pipeline
  /// drops frames rather than block). true: push() waits for room (is_live() = false).
  bool block_when_full = false;
  /// Throws std::invalid_argument (capacity outside [2, 1'000'000]).
  void validate() const;
};

enum class PushResult : std::uint8_t {
  queued,
  full,        // refused: no free slot (counted in SourceCounters::queue_full)
  wrong_size,  // not 1206 bytes on the data port / 512 on the position port (counted)
  closed,      // close() or request_stop() was called
};

class PacketQueueSource final : public PacketSource {
 public:
  explicit PacketQueueSource(const PushSourceConfig& config = {});
  ~PacketQueueSource() override;
  PacketQueueSource(const PacketQueueSource&) = delete;
  PacketQueueSource& operator=(const PacketQueueSource&) = delete;

  /// Queues a copy of `payload`, received at `receive_time_ns` (ns since the epoch: the
  /// time base of the packet stamps' hour) on `port`, sent by `from` (optional).
  PushResult push(std::span<const std::byte> payload, std::int64_t receive_time_ns,
                  PacketPort port, const SourceAddress& from = {});
  /// No more packets: next() drains the queue, then reports end_of_file.
  void close();

  SourceStatus next(PacketView& out, int timeout_ms) override;
  void request_stop() override;
  /// As of the latest next() call (the reading thread's view).
  [[nodiscard]] const SourceCounters& counters() const override;
  [[nodiscard]] bool is_live() const override;
  [[nodiscard]] std::string describe() const override;

  /// Packets refused because the queue was full, up to now (any thread).
  [[nodiscard]] std::uint64_t queue_full_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground
