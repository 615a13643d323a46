// Loopback helpers for network tests: addresses, a sending socket bound to any 127.x.y.z
// (Linux answers the whole 127/8 on lo, so each address can stand for one sensor) and a
// port that was free a moment ago.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

namespace vlpground::test {

inline sockaddr_in loopback_address(const char* ip, std::uint16_t port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  REQUIRE(inet_pton(AF_INET, ip, &address.sin_addr) == 1);
  return address;
}

/// A UDP socket of the test, bound to `source_ip`; sends to 127.0.0.1.
class Sender {
 public:
  explicit Sender(const char* source_ip = "127.0.0.1") : fd_(::socket(AF_INET, SOCK_DGRAM, 0)) {
    REQUIRE(fd_ >= 0);
    const sockaddr_in self = loopback_address(source_ip, 0);
    REQUIRE(::bind(fd_, reinterpret_cast<const sockaddr*>(&self), sizeof self) == 0);
  }
  ~Sender() { ::close(fd_); }
  Sender(const Sender&) = delete;
  Sender& operator=(const Sender&) = delete;

  void send(const std::vector<std::uint8_t>& payload, std::uint16_t port) const {
    const sockaddr_in to = loopback_address("127.0.0.1", port);
    const auto sent = ::sendto(fd_, payload.data(), payload.size(), 0,
                               reinterpret_cast<const sockaddr*>(&to), sizeof to);
    REQUIRE(sent == static_cast<ssize_t>(payload.size()));
  }

 private:
  int fd_;
};

/// A port that was free a moment ago (the kernel's choice for an ephemeral bind).
inline std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in address = loopback_address("127.0.0.1", 0);
  REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
  socklen_t length = sizeof address;
  REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0);
  ::close(fd);
  return ntohs(address.sin_port);
}

/// Two distinct free ports.
inline std::pair<std::uint16_t, std::uint16_t> free_port_pair() {
  const std::uint16_t first = free_port();
  std::uint16_t second = free_port();
  while (second == first) second = free_port();
  return {first, second};
}

}  // namespace vlpground::test
