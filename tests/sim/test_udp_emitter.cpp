// The live emitter sends every packet, to the right ports, paced by the capture timestamps.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>
#include <vector>

#include "vlpground/sim/udp_emitter.hpp"

using namespace vlpground;
using namespace vlpground::sim;
using Clock = std::chrono::steady_clock;

namespace {

// A UDP socket bound to 127.0.0.1 on an ephemeral port; receive timeout 3 s.
struct Receiver {
  int fd = -1;
  std::uint16_t port = 0;
  Receiver() {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    socklen_t n = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    port = ntohs(a.sin_port);
    int buffer = 4 << 20;
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
    timeval tv{3, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~Receiver() { ::close(fd); }
};

}  // namespace

TEST_CASE("UDP emitter streams all packets at the capture's pace", "[sim][udp]") {
  SimConfig c;
  c.scene = SceneKind::flat;
  c.frames = 1;
  const Simulator sim(c);
  Receiver data, position;
  UdpStreamConfig udp;
  udp.data_port = data.port;
  udp.position_port = position.port;
  udp.rate = 2.0;  // ~0.1 s of capture in ~0.05 s

  UdpStreamStats stats;
  std::thread sender([&] { stats = stream_udp(sim, udp); });
  struct Arrival {
    Clock::time_point at;
    std::uint32_t stamp_us;
  };
  std::vector<Arrival> arrivals;
  std::vector<std::uint8_t> buf(2048);
  while (arrivals.size() < sim.packet_count()) {
    const auto n = ::recv(data.fd, buf.data(), buf.size(), 0);
    if (n <= 0) break;  // timeout: a packet is missing
    REQUIRE(n == 1206);
    const std::uint32_t stamp = buf[1200] | (std::uint32_t{buf[1201]} << 8) |
                                (std::uint32_t{buf[1202]} << 16) | (std::uint32_t{buf[1203]} << 24);
    arrivals.push_back({Clock::now(), stamp});
  }
  sender.join();
  CHECK(stats.data_packets == sim.packet_count());
  CHECK(stats.send_errors == 0);
  REQUIRE(arrivals.size() == sim.packet_count());
  std::size_t positions = 0;
  while (positions < stats.position_packets) {
    const auto n = ::recv(position.fd, buf.data(), buf.size(), 0);
    if (n <= 0) break;
    CHECK(n == 512);
    ++positions;
  }
  CHECK(positions == sim.packet_count() / 14);

  // Arrival vs schedule: never early (the emitter waits for each packet's time), and the
  // lag spread stays far below the capture span (generous bound for loaded CI machines).
  double min_lag = 1e9, max_lag = -1e9;
  for (const Arrival& a : arrivals) {
    const double scheduled_s = (a.stamp_us - arrivals.front().stamp_us) * 1e-6 / udp.rate;
    const double arrived_s = std::chrono::duration<double>(a.at - arrivals.front().at).count();
    min_lag = std::min(min_lag, arrived_s - scheduled_s);
    max_lag = std::max(max_lag, arrived_s - scheduled_s);
  }
  const double span_s = (arrivals.back().stamp_us - arrivals.front().stamp_us) * 1e-6 / udp.rate;
  INFO("lag spread " << (max_lag - min_lag) * 1e3 << " ms over a " << span_s * 1e3
                     << " ms schedule");
  CHECK(min_lag > -0.02);
  CHECK(max_lag - min_lag < 0.5);
}

TEST_CASE("UDP emitter config is validated", "[sim][udp]") {
  UdpStreamConfig c;
  c.rate = 0.0;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
  c = UdpStreamConfig{};
  c.host.clear();
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
}
