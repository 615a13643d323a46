// Streams a simulated capture live over UDP, paced by the packets' capture timestamps.
//
// Thread-safety: stream_udp() blocks the calling thread; `should_stop` is polled between
// packets (it may read an atomic set by another thread).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "vlpground/sim/simulator.hpp"

namespace vlpground::sim {

struct UdpStreamConfig {
  std::string host = "127.0.0.1";  // destination (loopback unless the user gives another)
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;
  double rate = 1.0;  // 2.0 = twice real time
  bool loop = false;  // restart (stamps keep increasing) until stopped

  /// Throws std::invalid_argument with a clear message.
  void validate() const;
};

struct UdpStreamStats {
  std::uint64_t data_packets = 0;
  std::uint64_t position_packets = 0;
  std::uint64_t send_errors = 0;
};

/// Sends every data packet to host:data_port and every position packet to
/// host:position_port at (capture time - first capture time) / rate after the start.
/// Returns when all are sent (never with `loop` unless `should_stop` says so). Throws
/// std::runtime_error when the host cannot be resolved or the socket cannot be opened.
UdpStreamStats stream_udp(const Simulator& sim, const UdpStreamConfig& config,
                          const std::function<bool()>& should_stop = {});

}  // namespace vlpground::sim
