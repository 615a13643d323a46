// Live UDP reception: Boost.Asio opens, configures and binds the sockets; packets are read
// with recvmsg() on the native handles (kernel timestamps and drop counters come as control
// messages) and waited for with poll(), together with an eventfd that request_stop() signals.
#include <arpa/inet.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/multicast.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <string>

#include "packet_filter.hpp"
#include "vlpground/driver/packet_source.hpp"

namespace vlpground {

namespace asio = boost::asio;
using asio::ip::udp;

void UdpSourceConfig::validate() const {
  boost::system::error_code ec;
  asio::ip::make_address(bind_address, ec);
  if (ec) throw std::invalid_argument("udp source: bad bind_address '" + bind_address + "'");
  if (data_port == 0) throw std::invalid_argument("udp source: data_port must not be 0");
  if (position_port == data_port) {
    throw std::invalid_argument("udp source: data_port and position_port must differ");
  }
  if (!multicast_group.empty()) {
    const auto group = asio::ip::make_address(multicast_group, ec);
    if (ec || !group.is_multicast()) {
      throw std::invalid_argument("udp source: multicast_group '" + multicast_group +
                                  "' is not a multicast address");
    }
  }
  if (receive_buffer_bytes <= 0) {
    throw std::invalid_argument("udp source: receive_buffer_bytes must be positive");
  }
  (void)driver_detail::parse_sensor_address(sensor_address);
}

namespace {

constexpr std::size_t kMaxDatagramBytes = 2048;  // larger than any Velodyne packet

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::int64_t realtime_now_ns() {
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::string endpoint_text(const std::string& address, std::uint16_t port) {
  return "port " + std::to_string(port) + " on " + address;
}

void set_int_option(int fd, int level, int name, int value) {
  (void)::setsockopt(fd, level, name, &value, sizeof value);  // best effort: see callers
}

// Linux doubles the request for bookkeeping and caps SO_RCVBUF at net.core.rmem_max;
// SO_RCVBUFFORCE ignores the cap but needs CAP_NET_ADMIN, so it is tried first.
int set_receive_buffer(int fd, int bytes) {
  if (::setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &bytes, sizeof bytes) != 0) {
    (void)::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &bytes, sizeof bytes);
  }
  int granted = 0;
  socklen_t length = sizeof granted;
  (void)::getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &granted, &length);
  return granted;
}

[[noreturn]] void throw_bind_error(const boost::system::error_code& ec, const std::string& where) {
  if (ec.value() == EADDRINUSE) throw std::runtime_error(where + " is already in use");
  if (ec.value() == EACCES) {
    throw std::runtime_error("permission denied for " + where + " (ports below 1024 need root)");
  }
  if (ec.value() == EADDRNOTAVAIL) {
    throw std::runtime_error("cannot listen on " + where +
                             ": the address is not assigned to this host");
  }
  throw std::runtime_error("cannot listen on " + where + ": " + ec.message());
}

struct Endpoint {
  udp::socket socket;
  std::uint16_t port = 0;
  std::uint32_t kernel_drops = 0;  // cumulative, as SO_RXQ_OVFL reports it
};

/// Thread-safety: one thread calls next(); request_stop() from any thread.
class UdpSource final : public PacketSource {
 public:
  UdpSource(const UdpSourceConfig& config, int* granted_buffer_bytes) : config_(config) {
    filter_.data_port = config.data_port;
    filter_.position_port = config.position_port;
    filter_.sensor = driver_detail::parse_sensor_address(config.sensor_address);
    stop_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (stop_fd_ < 0) throw std::runtime_error("udp source: eventfd failed");
    const int granted = open_endpoint(config.data_port);
    if (config.position_port != 0) open_endpoint(config.position_port);
    if (granted_buffer_bytes != nullptr) *granted_buffer_bytes = granted;
    for (std::size_t i = 0; i < endpoint_count_; ++i) {
      poll_fds_[i] = {endpoints_[i]->socket.native_handle(), POLLIN, 0};
    }
    poll_fds_[endpoint_count_] = {stop_fd_, POLLIN, 0};
  }

  ~UdpSource() override {
    for (auto& endpoint : endpoints_) endpoint.reset();
    if (stop_fd_ >= 0) ::close(stop_fd_);
  }

  UdpSource(const UdpSource&) = delete;
  UdpSource& operator=(const UdpSource&) = delete;

  SourceStatus next(PacketView& out, int timeout_ms) override {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::milliseconds(std::max(timeout_ms, 0));
    for (;;) {
      if (stop_.load(std::memory_order_acquire)) return SourceStatus::stopped;
      if (receive_any(out)) return SourceStatus::packet;
      int wait_ms = -1;
      if (timeout_ms >= 0) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) return SourceStatus::timeout;
        wait_ms = static_cast<int>(left.count());
      }
      const int ready = ::poll(poll_fds_.data(), endpoint_count_ + 1, wait_ms);
      if (ready < 0 && errno != EINTR) return SourceStatus::timeout;  // cannot happen on valid fds
    }
  }

  void request_stop() override {
    stop_.store(true, std::memory_order_release);
    const std::uint64_t one = 1;
    (void)!::write(stop_fd_, &one, sizeof one);
  }

  [[nodiscard]] const SourceCounters& counters() const override { return counters_; }
  [[nodiscard]] bool is_live() const override { return true; }

  [[nodiscard]] std::string describe() const override {
    std::string text = "udp " + config_.bind_address + ":" + std::to_string(config_.data_port);
    if (config_.position_port != 0)
      text += " (position " + std::to_string(config_.position_port) + ")";
    if (!config_.multicast_group.empty()) text += " group " + config_.multicast_group;
    return text;
  }

 private:
  enum class Receive : std::uint8_t { packet, skipped, empty };

  // Round-robin over the sockets so a busy data port cannot starve the position port.
  // Drains datagrams that are not ours without waiting.
  bool receive_any(PacketView& out) {
    for (std::size_t tried = 0; tried < endpoint_count_; ++tried) {
      const std::size_t index = (next_endpoint_ + tried) % endpoint_count_;
      Receive result;
      while ((result = receive_one(*endpoints_[index], out)) == Receive::skipped) {
        if (stop_.load(std::memory_order_acquire)) return false;
      }
      if (result == Receive::packet) {
        next_endpoint_ = (index + 1) % endpoint_count_;
        return true;
      }
    }
    return false;
  }

  Receive receive_one(Endpoint& endpoint, PacketView& out) {
    sockaddr_storage from{};
    iovec io{buffer_.data(), buffer_.size()};
    msghdr message{};
    message.msg_name = &from;
    message.msg_namelen = sizeof from;
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control_.data();
    message.msg_controllen = control_.size();
    const ssize_t received = ::recvmsg(endpoint.socket.native_handle(), &message, MSG_DONTWAIT);
    if (received < 0) {
      if (errno == EINTR) return Receive::skipped;
      if (errno != EAGAIN && errno != EWOULDBLOCK) clear_socket_error(endpoint);
      return Receive::empty;
    }
    ++counters_.records;
    const std::int64_t kernel_ns = read_control(message, endpoint);
    if ((message.msg_flags & MSG_TRUNC) != 0) {
      ++counters_.skipped_wrong_size;
      return Receive::skipped;
    }
    driver_detail::UdpDatagram datagram;
    datagram.source = source_address(from);
    datagram.source_port = source_port(from);
    datagram.destination_port = endpoint.port;
    datagram.payload = {buffer_.data(), static_cast<std::size_t>(received)};
    const auto kind = filter_.accept(datagram, counters_);
    if (!kind) return Receive::skipped;
    out.bytes = datagram.payload;
    out.kind = *kind;
    out.source = driver_detail::to_source_address(datagram);
    out.receive_ns = kernel_ns != 0 ? kernel_ns : realtime_now_ns();
    out.steady_receive_ns = steady_now_ns();
    return Receive::packet;
  }

  // Returns the kernel receive stamp (0 if absent); updates the drop counter.
  std::int64_t read_control(msghdr& message, Endpoint& endpoint) {
    std::int64_t stamp_ns = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec stamp{};
        std::memcpy(&stamp, CMSG_DATA(c), sizeof stamp);
        stamp_ns = static_cast<std::int64_t>(stamp.tv_sec) * 1'000'000'000 + stamp.tv_nsec;
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t drops = 0;
        std::memcpy(&drops, CMSG_DATA(c), sizeof drops);
        counters_.kernel_drops += drops - endpoint.kernel_drops;  // wraps correctly
        endpoint.kernel_drops = drops;
      }
    }
    return stamp_ns;
  }

  static driver_detail::IpAddress source_address(const sockaddr_storage& from) {
    driver_detail::IpAddress address;
    if (from.ss_family == AF_INET) {
      sockaddr_in v4{};
      std::memcpy(&v4, &from, sizeof v4);
      address.version = 4;
      std::memcpy(address.bytes.data(), &v4.sin_addr, 4);
    } else if (from.ss_family == AF_INET6) {
      sockaddr_in6 v6{};
      std::memcpy(&v6, &from, sizeof v6);
      address.version = 6;
      std::memcpy(address.bytes.data(), &v6.sin6_addr, 16);
    }
    return address;
  }

  static std::uint16_t source_port(const sockaddr_storage& from) {
    in_port_t port = 0;
    if (from.ss_family == AF_INET) {
      sockaddr_in v4{};
      std::memcpy(&v4, &from, sizeof v4);
      port = v4.sin_port;
    } else if (from.ss_family == AF_INET6) {
      sockaddr_in6 v6{};
      std::memcpy(&v6, &from, sizeof v6);
      port = v6.sin6_port;
    }
    return ntohs(port);
  }

  static void clear_socket_error(Endpoint& endpoint) {
    int error = 0;
    socklen_t length = sizeof error;
    (void)::getsockopt(endpoint.socket.native_handle(), SOL_SOCKET, SO_ERROR, &error, &length);
  }

  // Opens, configures and binds one socket; returns the granted receive buffer size.
  int open_endpoint(std::uint16_t port) {
    boost::system::error_code ec;
    const auto bind_address = asio::ip::make_address(config_.bind_address, ec);
    asio::ip::address listen_address = bind_address;
    asio::ip::address group;
    if (!config_.multicast_group.empty()) {
      // Bound to the group itself so only its traffic arrives; joined on the bind interface.
      group = asio::ip::make_address(config_.multicast_group, ec);
      listen_address = group;
    }
    const udp::endpoint where(listen_address, port);
    const std::string where_text = endpoint_text(listen_address.to_string(), port);
    auto endpoint = std::make_unique<Endpoint>(Endpoint{udp::socket(io_), port, 0});
    udp::socket& socket = endpoint->socket;
    if (socket.open(where.protocol(), ec)) {
      throw std::runtime_error("cannot open a UDP socket for " + where_text + ": " + ec.message());
    }
    const int fd = socket.native_handle();
    if (config_.reuse_address) {
      socket.set_option(udp::socket::reuse_address(true), ec);
      set_int_option(fd, SOL_SOCKET, SO_REUSEPORT, 1);
    }
    const int granted = set_receive_buffer(fd, config_.receive_buffer_bytes);
    set_int_option(fd, SOL_SOCKET, SO_RXQ_OVFL, 1);
    set_int_option(fd, SOL_SOCKET, SO_TIMESTAMPNS, 1);
    if (socket.bind(where, ec)) throw_bind_error(ec, where_text);
    if (!group.is_unspecified()) join_group(socket, group, bind_address);
    if (socket.non_blocking(true, ec)) {
      throw std::runtime_error("cannot make the socket for " + where_text + " non-blocking");
    }
    endpoints_[endpoint_count_++] = std::move(endpoint);
    return granted;
  }

  static void join_group(udp::socket& socket, const asio::ip::address& group,
                         const asio::ip::address& interface_address) {
    boost::system::error_code ec;
    if (group.is_v4()) {
      const auto interface_v4 =
          interface_address.is_v4() ? interface_address.to_v4() : asio::ip::address_v4::any();
      socket.set_option(asio::ip::multicast::join_group(group.to_v4(), interface_v4), ec);
    } else {
      socket.set_option(asio::ip::multicast::join_group(group.to_v6()), ec);
    }
    if (ec) {
      throw std::runtime_error("cannot join multicast group " + group.to_string() + " on " +
                               interface_address.to_string() + ": " + ec.message());
    }
  }

  UdpSourceConfig config_;
  driver_detail::PacketFilter filter_;
  SourceCounters counters_;
  asio::io_context io_;
  std::array<std::unique_ptr<Endpoint>, 2> endpoints_;
  std::size_t endpoint_count_ = 0;
  std::size_t next_endpoint_ = 0;
  std::array<pollfd, 3> poll_fds_{};
  int stop_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::array<std::uint8_t, kMaxDatagramBytes> buffer_{};
  alignas(cmsghdr) std::array<char, 256> control_{};
};

}  // namespace

std::unique_ptr<PacketSource> open_udp_source(const UdpSourceConfig& config,
                                              int* granted_buffer_bytes) {
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());  // the documented contract: bad address = runtime_error
  }
  return std::make_unique<UdpSource>(config, granted_buffer_bytes);
}

}  // namespace vlpground
