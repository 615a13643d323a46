// The live emitter sends every packet, to the right ports, paced by the capture timestamps.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <atomic>
#include <chrono>
#include <thread>
#include <cstring>
#include <vector>

#include "loopback.hpp"
#include "vlpground/driver/udp_router.hpp"
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

TEST_CASE("UDP emitter: two sensors from two source addresses, faults injected and counted",
          "[sim][udp]") {
  SimConfig c;
  c.scene = SceneKind::flat;
  c.frames = 1;
  const Simulator first(c);
  c.seed = 2;
  c.mode = ReturnMode::dual;
  const Simulator second(c);

  const auto [data_port, position_port] = vlpground::test::free_port_pair();
  UdpRouterConfig routing;
  routing.bind_address = "127.0.0.1";
  routing.sensors = {{"127.0.0.2", data_port, position_port},
                     {"127.0.0.3", data_port, position_port}};
  auto router = open_udp_router(routing);

  UdpStreamConfig a;
  a.data_port = data_port;
  a.position_port = position_port;
  a.rate = 4.0;
  a.source_address = "127.0.0.2";
  UdpStreamConfig b = a;
  b.source_address = "127.0.0.3";
  b.faults = {.loss = 0.05, .reorder = 0.05, .truncate = 0.05, .junk = 0.5, .seed = 7};

  UdpStreamStats sent_a, sent_b;
  std::thread sender_a([&] { sent_a = stream_udp(first, a); });
  std::thread sender_b([&] { sent_b = stream_udp(second, b); });
  std::uint64_t data[2] = {0, 0}, reordered_b = 0;
  std::uint32_t last_stamp_b = 0;
  RoutedPacket packet;
  // Every datagram arrives on loopback; stop after 2 s without one (the senders are done).
  while (router->next(packet, 2000) == SourceStatus::packet) {
    if (packet.packet.kind != PacketKind::data) continue;
    ++data[packet.sensor];
    if (packet.sensor == 1) {
      std::uint32_t stamp = 0;
      std::memcpy(&stamp, packet.packet.bytes.data() + 1200, 4);
      reordered_b += stamp < last_stamp_b ? 1 : 0;
      last_stamp_b = std::max(stamp, last_stamp_b);
    }
  }
  sender_a.join();
  sender_b.join();

  CHECK(sent_a.data_packets == first.packet_count());
  CHECK(sent_a.datagrams() == sent_a.data_packets + sent_a.position_packets);
  CHECK(sent_b.lost > 0);
  CHECK(sent_b.reordered > 0);
  CHECK(sent_b.truncated > 0);
  CHECK(sent_b.junk > 0);
  std::uint64_t positions_b = 0;
  SimulatedPositionPacket position;
  for (std::uint64_t i = 0; i < second.packet_count(); ++i) {
    if (second.position_after(i, position)) ++positions_b;
  }
  CHECK(sent_b.data_packets + sent_b.position_packets + sent_b.lost + sent_b.truncated ==
        second.packet_count() + positions_b);
  CHECK(reordered_b == sent_b.reordered);

  const UdpRouterCounters& counters = router->counters();
  CHECK(counters.kernel_drops == 0);
  CHECK(counters.unknown_source == 0);
  CHECK(counters.records == sent_a.datagrams() + sent_b.datagrams());
  CHECK(counters.sensors[0].records == sent_a.datagrams());
  CHECK(counters.sensors[1].records == sent_b.datagrams());
  CHECK(data[0] == sent_a.data_packets);
  // Junk of exactly 1206 bytes passes the size check (the decoder refuses it later).
  CHECK(data[1] >= sent_b.data_packets);
  CHECK(data[1] <= sent_b.data_packets + sent_b.junk / 2200 + 1);
  CHECK(counters.sensors[1].skipped_wrong_size + data[1] + counters.sensors[1].position_packets ==
        sent_b.datagrams());
}

TEST_CASE("UDP emitter: a source address not on this host is a clear error", "[sim][udp]") {
  SimConfig c;
  c.frames = 1;
  const Simulator sim(c);
  UdpStreamConfig udp;
  udp.source_address = "192.0.2.1";  // TEST-NET-1, never assigned here
  CHECK_THROWS_WITH(stream_udp(sim, udp), Catch::Contains("cannot send from '192.0.2.1'"));
}

TEST_CASE("UDP emitter: a prepared stream restarts its clock at every play", "[sim][udp]") {
  SimConfig c;
  c.scene = SceneKind::flat;
  c.frames = 1;
  const Simulator sim(c);
  Receiver data, position;
  UdpStreamConfig udp;
  udp.data_port = data.port;
  udp.position_port = position.port;
  udp.rate = 8.0;
  PreparedStream stream(sim);
  std::vector<std::uint8_t> buf(2048);
  auto stamp_of_next = [&]() -> std::int64_t {
    if (::recv(data.fd, buf.data(), buf.size(), 0) != 1206) return -1;
    return buf[1200] | (std::int64_t{buf[1201]} << 8) | (std::int64_t{buf[1202]} << 16) |
           (std::int64_t{buf[1203]} << 24);
  };
  auto read_stamps = [&](std::uint64_t count) {
    std::vector<std::int64_t> stamps;
    for (std::uint64_t i = 0; i < count; ++i) stamps.push_back(stamp_of_next());
    return stamps;
  };

  // A looping play: the second pass continues the clock.
  UdpStreamConfig looping = udp;
  looping.loop = true;
  std::atomic<bool> enough{false};
  std::thread sender([&] { stream.play(looping, [&] { return enough.load(); }); });
  const std::vector<std::int64_t> first = read_stamps(sim.packet_count() + 3);
  enough = true;
  sender.join();
  REQUIRE(first.back() >= 0);
  const auto n = static_cast<std::ptrdiff_t>(sim.packet_count());
  CHECK(first[static_cast<std::size_t>(n)] > first[static_cast<std::size_t>(n - 1)]);
  while (::recv(data.fd, buf.data(), buf.size(), MSG_DONTWAIT) > 0) {
  }

  // Playing again starts at the capture's own first stamp: a sensor restart.
  std::thread again([&] { stream.play(udp); });
  const std::int64_t restarted = stamp_of_next();
  again.join();
  CHECK(restarted == first.front());
}
