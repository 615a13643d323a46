// Live UDP source on loopback only: datagrams from test-local sockets, bounded waits (a
// waiting next() returns as soon as the datagram is there), no sleeps.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <latch>
#include <stdexcept>
#include <string>
#include <thread>

#include "capture_builder.hpp"
#include "loopback.hpp"
#include "vlpground/driver/packet_source.hpp"

using namespace vlpground;
using vlpground::test::Bytes;
using vlpground::test::pattern_payload;
using vlpground::test::free_port;
using vlpground::test::loopback_address;
using vlpground::test::Sender;

namespace {

constexpr int kWaitMs = 5000;  // upper bound only; loopback datagrams are there at once

UdpSourceConfig loopback_config() {
  UdpSourceConfig config;
  config.bind_address = "127.0.0.1";
  config.data_port = free_port();
  do {
    config.position_port = free_port();
  } while (config.position_port == config.data_port);
  return config;
}

Bytes received_bytes(const PacketView& view) { return Bytes(view.bytes.begin(), view.bytes.end()); }

}  // namespace

TEST_CASE("udp: data and position datagrams arrive with their bytes, kind and stamps") {
  const UdpSourceConfig config = loopback_config();
  int granted = 0;
  auto source = open_udp_source(config, &granted);
  CHECK(source->is_live());
  CHECK(source->progress() == -1.0);
  CHECK(source->describe().find(std::to_string(config.data_port)) != std::string::npos);

  WARN("receive buffer: asked " << config.receive_buffer_bytes << " bytes, kernel granted "
                                << granted);
  CHECK(granted > 0);
  std::ifstream rmem_max_file("/proc/sys/net/core/rmem_max");
  long rmem_max = 0;
  if (rmem_max_file >> rmem_max) {  // Linux grants twice the request, capped at rmem_max
    CHECK(granted >= 2 * std::min<long>(config.receive_buffer_bytes, rmem_max));
  }

  Sender sender;
  sender.send(pattern_payload(1206, 1), config.data_port);
  sender.send(pattern_payload(100, 0), config.data_port);  // wrong size
  sender.send(pattern_payload(512, 2), config.position_port);
  sender.send(pattern_payload(1206, 3), config.data_port);

  PacketView view;
  int data_seen = 0;
  bool position_seen = false;
  for (int i = 0; i < 3; ++i) {
    REQUIRE(source->next(view, kWaitMs) == SourceStatus::packet);
    CHECK(view.receive_ns > 0);
    CHECK(view.steady_receive_ns > 0);
    if (view.kind == PacketKind::position) {
      CHECK(received_bytes(view) == pattern_payload(512, 2));
      position_seen = true;
    } else {
      // Datagrams of one socket keep their order.
      CHECK(received_bytes(view) == pattern_payload(1206, data_seen == 0 ? 1 : 3));
      ++data_seen;
    }
  }
  CHECK(data_seen == 2);
  CHECK(position_seen);
  CHECK(source->next(view, 0) == SourceStatus::timeout);
  const SourceCounters& c = source->counters();
  CHECK(c.records == 4);
  CHECK(c.data_packets == 2);
  CHECK(c.position_packets == 1);
  CHECK(c.skipped_wrong_size == 1);
}

TEST_CASE("udp: next() times out when nothing arrives") {
  auto source = open_udp_source(loopback_config());
  PacketView view;
  CHECK(source->next(view, 0) == SourceStatus::timeout);
  CHECK(source->next(view, 5) == SourceStatus::timeout);
  CHECK(source->counters().records == 0);
}

TEST_CASE("udp: request_stop() from another thread ends a blocked next()") {
  auto source = open_udp_source(loopback_config());
  std::latch about_to_wait(1);
  std::thread stopper([&] {
    about_to_wait.wait();
    source->request_stop();
  });
  about_to_wait.count_down();
  PacketView view;
  const SourceStatus status = source->next(view, -1);  // would wait forever without the stop
  stopper.join();
  CHECK(status == SourceStatus::stopped);
  CHECK(source->next(view, 0) == SourceStatus::stopped);
}

TEST_CASE("udp: the sensor address filter drops other senders") {
  UdpSourceConfig config = loopback_config();
  config.sensor_address = "127.0.0.1";
  auto source = open_udp_source(config);
  Sender stranger("127.0.0.2");
  Sender sensor("127.0.0.1");
  stranger.send(pattern_payload(1206, 7), config.data_port);
  sensor.send(pattern_payload(1206, 8), config.data_port);
  PacketView view;
  REQUIRE(source->next(view, kWaitMs) == SourceStatus::packet);
  CHECK(received_bytes(view) == pattern_payload(1206, 8));
  // The sender's address travels with the packet (routing several sensors by address).
  CHECK(view.source.version == 4);
  CHECK(view.source.bytes[0] == 127);
  CHECK(view.source.bytes[3] == 1);
  CHECK(view.source.port != 0);
  CHECK(view.source.to_string().rfind("127.0.0.1:", 0) == 0);
  CHECK(source->counters().skipped_address == 1);
  CHECK(source->counters().records == 2);
}

TEST_CASE("udp: a port in use is a clear error, unless both ask for reuse") {
  UdpSourceConfig config = loopback_config();
  config.position_port = 0;  // position off: only the data socket
  auto first = open_udp_source(config);
  try {
    open_udp_source(config);
    FAIL("second bind succeeded");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message ==
          "port " + std::to_string(config.data_port) + " on 127.0.0.1 is already in use");
  }
  first.reset();
  config.reuse_address = true;
  auto shared_a = open_udp_source(config);
  CHECK_NOTHROW(open_udp_source(config));
}

TEST_CASE("udp: bad addresses are runtime errors naming the problem") {
  UdpSourceConfig config = loopback_config();
  auto expect_error = [&](const std::string& needle) {
    try {
      open_udp_source(config);
      FAIL("no error");
    } catch (const std::runtime_error& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  };
  SECTION("unparsable bind address") {
    config.bind_address = "not-an-address";
    CHECK_THROWS_AS(config.validate(), std::invalid_argument);
    expect_error("not-an-address");
  }
  SECTION("address not on this host") {
    config.bind_address = "192.0.2.55";  // TEST-NET-1
    expect_error("not assigned");
  }
  SECTION("not a multicast group") {
    config.multicast_group = "10.1.1.1";
    expect_error("multicast");
  }
  SECTION("bad sensor address") {
    config.sensor_address = "1.2.3";
    expect_error("sensor_address");
  }
  SECTION("same port twice") {
    config.position_port = config.data_port;
    CHECK_THROWS_AS(config.validate(), std::invalid_argument);
  }
}

TEST_CASE("udp: overflowing a small receive buffer is counted as kernel drops") {
  UdpSourceConfig config = loopback_config();
  config.position_port = 0;
  config.receive_buffer_bytes = 1;  // the kernel raises it to its minimum (a few KiB)
  int granted = 0;
  auto source = open_udp_source(config, &granted);
  INFO("granted " << granted);
  Sender sender;
  const int burst = 64;  // far more than the minimum buffer holds
  for (int i = 0; i < burst; ++i) sender.send(pattern_payload(1206, 1), config.data_port);
  PacketView view;
  int received = 0;
  while (source->next(view, 0) == SourceStatus::packet) ++received;
  // The drop count travels with later datagrams: send a marker and read up to it.
  sender.send(pattern_payload(1206, 2), config.data_port);
  for (;;) {
    REQUIRE(source->next(view, kWaitMs) == SourceStatus::packet);
    ++received;
    if (received_bytes(view) == pattern_payload(1206, 2)) break;
  }
  CHECK(received < burst);
  CHECK(source->counters().kernel_drops == static_cast<std::uint64_t>(burst + 1 - received));
}

TEST_CASE("udp: IPv6 loopback with an IPv6 sensor filter") {
  const int sender = ::socket(AF_INET6, SOCK_DGRAM, 0);
  sockaddr_in6 address{};
  address.sin6_family = AF_INET6;
  address.sin6_addr = in6addr_loopback;
  if (sender < 0 || ::bind(sender, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    if (sender >= 0) ::close(sender);
    WARN("skipped: no IPv6 loopback here");
    return;
  }
  UdpSourceConfig config;
  config.bind_address = "::1";
  config.data_port = free_port();  // an IPv4 probe; the IPv6 port space is separate but alike
  config.position_port = 0;
  config.sensor_address = "::1";
  std::unique_ptr<PacketSource> source;
  try {
    source = open_udp_source(config);
  } catch (const std::runtime_error& e) {
    ::close(sender);
    WARN("skipped: " << e.what());
    return;
  }
  address.sin6_port = htons(config.data_port);
  const Bytes payload = pattern_payload(1206, 6);
  REQUIRE(::sendto(sender, payload.data(), payload.size(), 0,
                   reinterpret_cast<const sockaddr*>(&address), sizeof address) == 1206);
  ::close(sender);
  PacketView view;
  REQUIRE(source->next(view, kWaitMs) == SourceStatus::packet);
  CHECK(received_bytes(view) == payload);
  CHECK(source->counters().skipped_address == 0);
}

TEST_CASE("udp: multicast group joined on the loopback interface") {
  UdpSourceConfig config = loopback_config();
  config.position_port = 0;
  config.multicast_group = "239.255.76.67";
  std::unique_ptr<PacketSource> source;
  try {
    source = open_udp_source(config);
  } catch (const std::runtime_error& e) {
    WARN("skipped: " << e.what());
    return;
  }
  CHECK(source->describe().find("239.255.76.67") != std::string::npos);
  const int sender = ::socket(AF_INET, SOCK_DGRAM, 0);
  in_addr interface_address{};
  REQUIRE(inet_pton(AF_INET, "127.0.0.1", &interface_address) == 1);
  REQUIRE(::setsockopt(sender, IPPROTO_IP, IP_MULTICAST_IF, &interface_address,
                       sizeof interface_address) == 0);
  const sockaddr_in group = loopback_address("239.255.76.67", config.data_port);
  const Bytes payload = pattern_payload(1206, 9);
  const auto sent = ::sendto(sender, payload.data(), payload.size(), 0,
                             reinterpret_cast<const sockaddr*>(&group), sizeof group);
  ::close(sender);
  if (sent != static_cast<ssize_t>(payload.size())) {
    WARN("skipped: no multicast route on loopback here");
    return;
  }
  PacketView view;
  REQUIRE(source->next(view, kWaitMs) == SourceStatus::packet);
  CHECK(view.kind == PacketKind::data);
  CHECK(received_bytes(view) == payload);
}
