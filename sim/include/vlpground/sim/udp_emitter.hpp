// Streams a simulated capture live over UDP, paced by the packets' capture timestamps.
//
// Thread-safety: stream_udp() blocks the calling thread; `should_stop` is polled between
// packets (it may read an atomic set by another thread).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "vlpground/sim/simulator.hpp"

namespace vlpground::sim {

/// Faults injected into the stream (soak and robustness tests). Each is drawn per packet from
/// a deterministic random sequence (`seed`) and counted in UdpStreamStats.
struct UdpFaults {
  double loss = 0.0;      // fraction of packets not sent
  double reorder = 0.0;   // fraction of packets held back and sent after the next one
  double truncate = 0.0;  // fraction of data packets sent cut short (1..1205 bytes)
  double junk = 0.0;      // junk datagrams per packet, to the data port, of every size in turn
                          // (0, 1, 2, ... 2199 bytes, random content; 1206 and 512 included)
  std::uint64_t seed = 1;
  [[nodiscard]] bool any() const { return loss > 0 || reorder > 0 || truncate > 0 || junk > 0; }
};

struct UdpStreamConfig {
  std::string host = "127.0.0.1";  // destination (loopback unless the user gives another)
  /// Local address the packets are sent from (empty: the kernel's choice). Two emitters on
  /// 127.0.0.2 and 127.0.0.3 look like two sensors to a receiver routing by source address.
  std::string source_address;
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;
  double rate = 1.0;  // 2.0 = twice real time
  bool loop = false;  // restart (stamps keep increasing) until stopped
  UdpFaults faults;

  /// Throws std::invalid_argument with a clear message.
  void validate() const;
};

struct UdpStreamStats {
  std::uint64_t data_packets = 0;
  std::uint64_t position_packets = 0;
  std::uint64_t send_errors = 0;
  // Injected faults (UdpFaults). data_packets counts whole data packets sent, reordered
  // ones included; `truncated` and `junk` datagrams are sent on top of them.
  std::uint64_t lost = 0;
  std::uint64_t reordered = 0;
  std::uint64_t truncated = 0;
  std::uint64_t junk = 0;
  /// Datagrams handed to the kernel.
  [[nodiscard]] std::uint64_t datagrams() const {
    return data_packets + position_packets + truncated + junk;
  }
  UdpStreamStats& operator+=(const UdpStreamStats& o);
};

/// Sends every data packet to host:data_port and every position packet to
/// host:position_port at (capture time - first capture time) / rate after the start.
/// Throws std::invalid_argument for a source_address not on this host or a fault fraction
/// outside [0, 1] (junk: [0, 100]).
/// Returns when all are sent (never with `loop` unless `should_stop` says so). Throws
/// std::runtime_error when the host cannot be resolved or the socket cannot be opened.
UdpStreamStats stream_udp(const Simulator& sim, const UdpStreamConfig& config,
                          const std::function<bool()>& should_stop = {});

/// A simulated capture encoded once and streamed as often as wanted (soak tests replay their
/// captures for an hour without simulating them again). Each play() starts at the capture's
/// own stamps, so playing again looks like a sensor restart (time jumps back).
/// Thread-safety: one thread plays a PreparedStream at a time.
class PreparedStream {
 public:
  explicit PreparedStream(const Simulator& sim);
  ~PreparedStream();
  PreparedStream(PreparedStream&&) noexcept;
  PreparedStream& operator=(PreparedStream&&) noexcept;

  /// As stream_udp().
  UdpStreamStats play(const UdpStreamConfig& config, const std::function<bool()>& should_stop = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground::sim
