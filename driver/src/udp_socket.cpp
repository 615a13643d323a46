#include "udp_socket.hpp"

#include <arpa/inet.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/multicast.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace vlpground::driver_detail {

namespace asio = boost::asio;
using asio::ip::udp;

namespace {

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
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

void join_group(udp::socket& socket, const asio::ip::address& group,
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

IpAddress source_address(const sockaddr_storage& from) {
  IpAddress address;
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

std::uint16_t source_port(const sockaddr_storage& from) {
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

}  // namespace

std::int64_t realtime_now_ns() {
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

void validate_socket_options(const UdpSocketOptions& options, const std::string& what) {
  boost::system::error_code ec;
  asio::ip::make_address(options.bind_address, ec);
  if (ec) throw std::invalid_argument(what + ": bad bind_address '" + options.bind_address + "'");
  if (!options.multicast_group.empty()) {
    const auto group = asio::ip::make_address(options.multicast_group, ec);
    if (ec || !group.is_multicast()) {
      throw std::invalid_argument(what + ": multicast_group '" + options.multicast_group +
                                  "' is not a multicast address");
    }
  }
  if (options.receive_buffer_bytes <= 0) {
    throw std::invalid_argument(what + ": receive_buffer_bytes must be positive");
  }
}

SocketWaiter::SocketWaiter() : stop_fd_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
  if (stop_fd_ < 0) throw std::runtime_error("udp: eventfd failed");
  fds_.push_back({stop_fd_, POLLIN, 0});
}

SocketWaiter::~SocketWaiter() { ::close(stop_fd_); }

void SocketWaiter::add(int fd) { fds_.insert(fds_.end() - 1, pollfd{fd, POLLIN, 0}); }

void SocketWaiter::request_stop() {
  stop_.store(true, std::memory_order_release);
  const std::uint64_t one = 1;
  (void)!::write(stop_fd_, &one, sizeof one);
}

void SocketWaiter::wait(int wait_ms) {
  (void)::poll(fds_.data(), fds_.size(), wait_ms);  // EINTR or ready: the caller tries again
}

struct UdpSocket::Impl {
  asio::io_context io;
  udp::socket socket{io};
};

UdpSocket::UdpSocket(const UdpSocketOptions& options, std::uint16_t port)
    : impl_(std::make_unique<Impl>()), port_(port) {
  boost::system::error_code ec;
  const auto bind_address = asio::ip::make_address(options.bind_address, ec);
  asio::ip::address listen_address = bind_address;
  asio::ip::address group;
  if (!options.multicast_group.empty()) {
    // Bound to the group itself so only its traffic arrives; joined on the bind interface.
    group = asio::ip::make_address(options.multicast_group, ec);
    listen_address = group;
  }
  const udp::endpoint where(listen_address, port);
  const std::string where_text =
      "port " + std::to_string(port) + " on " + listen_address.to_string();
  udp::socket& socket = impl_->socket;
  if (socket.open(where.protocol(), ec)) {
    throw std::runtime_error("cannot open a UDP socket for " + where_text + ": " + ec.message());
  }
  const int fd = socket.native_handle();
  if (options.reuse_address) {
    socket.set_option(udp::socket::reuse_address(true), ec);
    set_int_option(fd, SOL_SOCKET, SO_REUSEPORT, 1);
  }
  granted_buffer_bytes_ = set_receive_buffer(fd, options.receive_buffer_bytes);
  set_int_option(fd, SOL_SOCKET, SO_RXQ_OVFL, 1);
  set_int_option(fd, SOL_SOCKET, SO_TIMESTAMPNS, 1);
  if (socket.bind(where, ec)) throw_bind_error(ec, where_text);
  if (!group.is_unspecified()) join_group(socket, group, bind_address);
  if (socket.non_blocking(true, ec)) {
    throw std::runtime_error("cannot make the socket for " + where_text + " non-blocking");
  }
}

UdpSocket::~UdpSocket() = default;

int UdpSocket::native_handle() const { return impl_->socket.native_handle(); }

ReadResult UdpSocket::read(ReceivedDatagram& out) {
  sockaddr_storage from{};
  iovec io{buffer_.data(), buffer_.size()};
  msghdr message{};
  message.msg_name = &from;
  message.msg_namelen = sizeof from;
  message.msg_iov = &io;
  message.msg_iovlen = 1;
  message.msg_control = control_.data();
  message.msg_controllen = control_.size();
  const int fd = native_handle();
  const ssize_t received = ::recvmsg(fd, &message, MSG_DONTWAIT);
  if (received < 0) {
    if (errno == EINTR) return ReadResult::interrupted;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      int error = 0;  // clears a pending socket error (ICMP) so the next read proceeds
      socklen_t length = sizeof error;
      (void)::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length);
    }
    return ReadResult::empty;
  }
  out.new_kernel_drops = 0;
  out.receive_ns = 0;
  for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
    if (c->cmsg_level != SOL_SOCKET) continue;
    if (c->cmsg_type == SCM_TIMESTAMPNS) {
      timespec stamp{};
      std::memcpy(&stamp, CMSG_DATA(c), sizeof stamp);
      out.receive_ns = static_cast<std::int64_t>(stamp.tv_sec) * 1'000'000'000 + stamp.tv_nsec;
    } else if (c->cmsg_type == SO_RXQ_OVFL) {
      std::uint32_t drops = 0;
      std::memcpy(&drops, CMSG_DATA(c), sizeof drops);
      out.new_kernel_drops = drops - kernel_drops_;  // wraps correctly
      kernel_drops_ = drops;
    }
  }
  if (out.receive_ns == 0) out.receive_ns = realtime_now_ns();
  out.steady_receive_ns = steady_now_ns();
  out.oversize = (message.msg_flags & MSG_TRUNC) != 0;
  out.source = source_address(from);
  out.source_port = source_port(from);
  out.payload = {buffer_.data(), static_cast<std::size_t>(received)};
  return ReadResult::datagram;
}

}  // namespace vlpground::driver_detail
