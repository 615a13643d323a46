// One bound UDP socket for live reception (private to the driver): Boost.Asio opens,
// configures and binds it; datagrams are read with recvmsg() on the native handle so the
// kernel receive stamp (SO_TIMESTAMPNS) and drop counter (SO_RXQ_OVFL) come with them.
// Shared by UdpSource (one sensor) and UdpRouter (several sensors told apart by address).
//
// Thread-safety: one thread reads a socket.
#pragma once

#include <poll.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "frame_parser.hpp"
#include "vlpground/driver/packet_source.hpp"

namespace vlpground::driver_detail {

inline constexpr std::size_t kMaxDatagramBytes = 2048;  // larger than any Velodyne packet

struct UdpSocketOptions {
  std::string bind_address = "0.0.0.0";
  std::string multicast_group;  // empty: none
  bool reuse_address = false;
  int receive_buffer_bytes = 4 * 1024 * 1024;
};

/// What one recvmsg() returned.
struct ReceivedDatagram {
  IpAddress source;
  std::uint16_t source_port = 0;
  std::span<const std::uint8_t> payload;  // into the socket's buffer, valid until next read
  bool oversize = false;                  // cut by the kernel (larger than kMaxDatagramBytes)
  std::int64_t receive_ns = 0;            // kernel stamp, else host realtime clock
  std::int64_t steady_receive_ns = 0;     // host steady clock (for latency)
  std::uint64_t new_kernel_drops = 0;     // drops the kernel reported since the last read
};

enum class ReadResult : std::uint8_t { datagram, interrupted, empty };

class UdpSocket {
 public:
  /// Binds `port`. Throws std::runtime_error with a one-line reason ("port 2368 on 0.0.0.0
  /// is already in use", permission, address not on this host, multicast join failed).
  UdpSocket(const UdpSocketOptions& options, std::uint16_t port);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  /// Non-blocking read of one datagram.
  ReadResult read(ReceivedDatagram& out);

  [[nodiscard]] int native_handle() const;
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] int granted_buffer_bytes() const { return granted_buffer_bytes_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::uint16_t port_ = 0;
  int granted_buffer_bytes_ = 0;
  std::uint32_t kernel_drops_ = 0;  // cumulative, as SO_RXQ_OVFL reports it
  std::array<std::uint8_t, kMaxDatagramBytes> buffer_{};
  alignas(16) std::array<char, 256> control_{};
};

/// Waits on sockets and on a stop signal (an eventfd) at once: the receive loop shared by
/// the live sources. Thread-safety: one thread calls next(); request_stop() from any.
class SocketWaiter {
 public:
  SocketWaiter();  // throws std::runtime_error when no eventfd can be made
  ~SocketWaiter();
  SocketWaiter(const SocketWaiter&) = delete;
  SocketWaiter& operator=(const SocketWaiter&) = delete;

  void add(int fd);
  void request_stop();
  [[nodiscard]] bool stop_requested() const { return stop_.load(std::memory_order_acquire); }

  /// Calls `receive()` (true: a packet is ready) until it succeeds, waiting for readable
  /// sockets in between, for at most `timeout_ms` (negative: no limit; 0: no wait).
  template <class Receive>
  SourceStatus next(int timeout_ms, Receive&& receive) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::milliseconds(std::max(timeout_ms, 0));
    for (;;) {
      if (stop_requested()) return SourceStatus::stopped;
      if (receive()) return SourceStatus::packet;
      int wait_ms = -1;
      if (timeout_ms >= 0) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) return SourceStatus::timeout;
        wait_ms = static_cast<int>(left.count());
      }
      wait(wait_ms);
    }
  }

 private:
  void wait(int wait_ms);
  std::vector<pollfd> fds_;  // sockets, then the eventfd last
  int stop_fd_ = -1;
  std::atomic<bool> stop_{false};
};

/// Throws std::invalid_argument when the bind address or multicast group is not usable
/// (`what` names the owner: "udp source", "udp router").
void validate_socket_options(const UdpSocketOptions& options, const std::string& what);

/// Host realtime clock, ns since epoch.
std::int64_t realtime_now_ns();

}  // namespace vlpground::driver_detail
