// Live reception from several sensors in one process: one socket per distinct port, each
// datagram routed to the sensor whose address and port it came from. Cars carry two to five
// VLP-16s, often all sending to port 2368, told apart only by their source address.
// Boost.Asio stays behind the implementation; this header has no third-party includes.
//
// Thread-safety: one thread calls next() and counters(); request_stop() from any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vlpground/driver/packet_source.hpp"

namespace vlpground {

/// Where one sensor's packets come from.
struct RoutedSensor {
  std::string address;  // the sensor's IPv4/IPv6 address; empty = any (one sensor only)
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;  // 0 = ignore its position packets
};

struct UdpRouterConfig {
  std::vector<RoutedSensor> sensors;  // index = the sensor's number in RoutedPacket
  std::string bind_address = "0.0.0.0";
  std::string multicast_group;  // empty: none
  bool reuse_address = false;   // SO_REUSEADDR + SO_REUSEPORT
  int receive_buffer_bytes = 4 * 1024 * 1024;  // per socket

  /// Throws std::invalid_argument: no sensor, a bad address, port 0, a sensor without an
  /// address beside others, two sensors with one address on one port, a port used for data
  /// by one sensor and for position packets by another, data_port == position_port.
  void validate() const;
};

struct UdpRouterCounters {
  std::uint64_t records = 0;         // datagrams read from all sockets
  std::uint64_t unknown_source = 0;  // from an address no sensor has on that port
  std::uint64_t kernel_drops = 0;    // SO_RXQ_OVFL over all sockets (sensor unknown)
  /// Per sensor: `records` routed to it, data/position packets passed on, wrong sizes.
  std::vector<SourceCounters> sensors;
  /// Every datagram read is in exactly one of these.
  [[nodiscard]] std::uint64_t accounted() const {
    std::uint64_t sum = unknown_source;
    for (const auto& s : sensors) sum += s.records;
    return sum;
  }
};

struct RoutedPacket {
  std::size_t sensor = 0;  // index into UdpRouterConfig::sensors
  PacketView packet;       // valid until the next call to next()
};

class UdpRouter {
 public:
  virtual ~UdpRouter() = default;
  /// Waits up to `timeout_ms` (0: do not wait; negative: no limit) for the next data or
  /// position packet of a known sensor. Other datagrams are counted and skipped. Never
  /// allocates. Returns packet, timeout or stopped.
  virtual SourceStatus next(RoutedPacket& out, int timeout_ms) = 0;
  /// Makes a blocked or future next() return `stopped`.
  virtual void request_stop() = 0;
  [[nodiscard]] virtual const UdpRouterCounters& counters() const = 0;
  /// One-line description ("udp 0.0.0.0 ports 2368, 8308: 2 sensors").
  [[nodiscard]] virtual std::string describe() const = 0;
};

/// Binds one socket per distinct port. Throws std::runtime_error with a one-line reason
/// (port in use, address not on this host, invalid configuration).
std::unique_ptr<UdpRouter> open_udp_router(const UdpRouterConfig& config);

}  // namespace vlpground
