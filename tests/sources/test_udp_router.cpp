// Several sensors in one process: datagrams routed by source address and port, strangers
// counted. Loopback only (127.0.0.2 and .3 stand for two sensors), bounded waits, no sleeps.
#include <catch2/catch.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "capture_builder.hpp"
#include "loopback.hpp"
#include "vlpground/driver/udp_router.hpp"

using namespace vlpground;
using vlpground::test::free_port_pair;
using vlpground::test::pattern_payload;
using vlpground::test::Sender;

namespace {

constexpr int kWaitMs = 5000;  // upper bound only; loopback datagrams are there at once

UdpRouterConfig two_sensors_on_one_port() {
  const auto [data, position] = free_port_pair();
  UdpRouterConfig config;
  config.bind_address = "127.0.0.1";
  config.sensors = {{"127.0.0.2", data, position}, {"127.0.0.3", data, position}};
  return config;
}

}  // namespace

TEST_CASE("udp router: two sensors on one port are told apart by source address") {
  const UdpRouterConfig config = two_sensors_on_one_port();
  const std::uint16_t data = config.sensors[0].data_port;
  const std::uint16_t position = config.sensors[0].position_port;
  auto router = open_udp_router(config);
  CHECK(router->describe().find(std::to_string(data)) != std::string::npos);
  CHECK(router->describe().find("2 sensors") != std::string::npos);

  Sender first("127.0.0.2"), second("127.0.0.3"), stranger("127.0.0.9");
  first.send(pattern_payload(1206, 1), data);
  stranger.send(pattern_payload(1206, 2), data);  // unknown address: counted, not routed
  second.send(pattern_payload(1206, 3), data);
  second.send(pattern_payload(100, 4), data);  // wrong size: counted for sensor 1
  first.send(pattern_payload(512, 5), position);

  // Sockets are read round-robin: the order within a port is kept, not across ports.
  RoutedPacket packet;
  std::vector<std::pair<std::size_t, std::uint8_t>> data_seen;  // sensor, first byte
  int positions = 0;
  for (int i = 0; i < 3; ++i) {
    REQUIRE(router->next(packet, kWaitMs) == SourceStatus::packet);
    CHECK(packet.packet.receive_ns > 0);
    if (packet.packet.kind == PacketKind::position) {
      CHECK(packet.sensor == 0);
      CHECK(packet.packet.bytes.size() == 512);
      ++positions;
    } else {
      CHECK(packet.packet.bytes.size() == 1206);
      data_seen.emplace_back(packet.sensor, packet.packet.bytes[0]);
    }
  }
  CHECK(positions == 1);
  const std::vector<std::pair<std::size_t, std::uint8_t>> expected = {
      {0, pattern_payload(1206, 1)[0]}, {1, pattern_payload(1206, 3)[0]}};
  CHECK(data_seen == expected);
  CHECK(router->next(packet, 0) == SourceStatus::timeout);

  const UdpRouterCounters& c = router->counters();
  CHECK(c.records == 5);
  CHECK(c.unknown_source == 1);
  CHECK(c.accounted() == c.records);
  REQUIRE(c.sensors.size() == 2);
  CHECK(c.sensors[0].records == 2);
  CHECK(c.sensors[0].data_packets == 1);
  CHECK(c.sensors[0].position_packets == 1);
  CHECK(c.sensors[1].records == 2);
  CHECK(c.sensors[1].data_packets == 1);
  CHECK(c.sensors[1].skipped_wrong_size == 1);
}

TEST_CASE("udp router: sensors on their own ports share nothing") {
  const auto [port_a, port_b] = free_port_pair();
  UdpRouterConfig config;
  config.bind_address = "127.0.0.1";
  config.sensors = {{"127.0.0.2", port_a, 0}, {"127.0.0.2", port_b, 0}};  // one host, two ports
  auto router = open_udp_router(config);
  Sender sender("127.0.0.2");
  sender.send(pattern_payload(1206, 1), port_b);
  sender.send(pattern_payload(1206, 2), port_a);
  RoutedPacket packet;
  std::size_t seen[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    REQUIRE(router->next(packet, kWaitMs) == SourceStatus::packet);
    ++seen[packet.sensor];
  }
  CHECK(seen[0] == 1);
  CHECK(seen[1] == 1);
}

TEST_CASE("udp router: request_stop wakes a waiting next()") {
  auto router = open_udp_router(two_sensors_on_one_port());
  router->request_stop();
  RoutedPacket packet;
  CHECK(router->next(packet, -1) == SourceStatus::stopped);
}

TEST_CASE("udp router: configuration errors are clear") {
  UdpRouterConfig config = two_sensors_on_one_port();
  auto message = [](const UdpRouterConfig& c) {
    try {
      c.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("valid");
  };
  CHECK(message(config) == "valid");
  SECTION("no sensor") {
    config.sensors.clear();
    CHECK(message(config) == "udp router: no sensor configured");
  }
  SECTION("a sensor without an address beside others") {
    config.sensors[1].address.clear();
    CHECK(message(config).find("has no address") != std::string::npos);
  }
  SECTION("one address twice on a port") {
    config.sensors[1].address = config.sensors[0].address;
    CHECK(message(config).find("both listen for 127.0.0.2") != std::string::npos);
  }
  SECTION("a port for data and for position packets") {
    config.sensors[1].data_port = config.sensors[0].position_port;
    config.sensors[1].position_port = 0;
    CHECK(message(config).find("one port for data and for position") != std::string::npos);
  }
  SECTION("a bad address") {
    config.sensors[0].address = "not-an-address";
    CHECK(message(config).find("not-an-address") != std::string::npos);
    CHECK_THROWS_AS(open_udp_router(config), std::runtime_error);
  }
}
