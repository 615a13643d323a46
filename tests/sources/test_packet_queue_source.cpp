// PacketQueueSource: packets pushed by the program come out of next() with their bytes,
// port, stamps and sender; the queue is bounded and counts what it refuses.
#include <catch2/catch.hpp>
#include <cstddef>
#include <thread>
#include <vector>

#include "capture_builder.hpp"
#include "vlpground/driver/packet_queue_source.hpp"

using namespace vlpground;
using namespace vlpground::test;

namespace {

std::span<const std::byte> as_bytes(const std::vector<std::uint8_t>& v) {
  return std::as_bytes(std::span<const std::uint8_t>(v));
}

std::vector<std::uint8_t> bytes_of(const PacketView& view) {
  return {view.bytes.begin(), view.bytes.end()};
}

SourceAddress address(std::uint8_t last) {
  SourceAddress a;
  a.version = 4;
  a.bytes = {192, 168, 1, last};
  a.port = 2368;
  return a;
}

}  // namespace

TEST_CASE("push source: packets come out in order with port, stamps and sender") {
  PacketQueueSource q;
  CHECK(q.is_live());
  const auto data = pattern_payload(1206, 1);
  const auto position = pattern_payload(512, 2);
  REQUIRE(q.push(as_bytes(data), 111, PacketPort::data, address(201)) == PushResult::queued);
  REQUIRE(q.push(as_bytes(position), 222, PacketPort::position) == PushResult::queued);
  CHECK(q.push(as_bytes(pattern_payload(100, 3)), 333, PacketPort::data) ==
        PushResult::wrong_size);

  PacketView view;
  REQUIRE(q.next(view, 0) == SourceStatus::packet);
  CHECK(bytes_of(view) == data);
  CHECK(view.kind == PacketKind::data);
  CHECK(view.receive_ns == 111);
  CHECK(view.steady_receive_ns > 0);
  CHECK(view.source == address(201));
  CHECK(view.source.to_string() == "192.168.1.201:2368");
  REQUIRE(q.next(view, 0) == SourceStatus::packet);
  CHECK(bytes_of(view) == position);
  CHECK(view.kind == PacketKind::position);
  CHECK(view.source.to_string() == "unknown");
  CHECK(q.next(view, 0) == SourceStatus::timeout);

  const SourceCounters& c = q.counters();
  CHECK(c.records == 3);
  CHECK(c.data_packets == 1);
  CHECK(c.position_packets == 1);
  CHECK(c.skipped_wrong_size == 1);
  CHECK(c.records == c.data_packets + c.position_packets + c.skipped());
}

TEST_CASE("push source: a full queue refuses and counts, close() drains then ends") {
  PushSourceConfig config;
  config.capacity_packets = 3;
  PacketQueueSource q(config);
  const auto data = pattern_payload(1206, 4);
  for (int i = 0; i < 3; ++i) REQUIRE(q.push(as_bytes(data), i, PacketPort::data) == PushResult::queued);
  CHECK(q.push(as_bytes(data), 3, PacketPort::data) == PushResult::full);
  CHECK(q.push(as_bytes(data), 4, PacketPort::data) == PushResult::full);
  CHECK(q.queue_full_count() == 2);
  q.close();
  CHECK(q.push(as_bytes(data), 5, PacketPort::data) == PushResult::closed);
  PacketView view;
  for (int i = 0; i < 3; ++i) {
    REQUIRE(q.next(view, 0) == SourceStatus::packet);
    CHECK(view.receive_ns == i);
  }
  CHECK(q.next(view, 0) == SourceStatus::end_of_file);
  CHECK(q.counters().queue_full == 2);
  CHECK(q.counters().records == q.counters().data_packets + q.counters().skipped());
}

TEST_CASE("push source: block_when_full waits for the reader, nothing lost") {
  PushSourceConfig config;
  config.capacity_packets = 2;
  config.block_when_full = true;
  PacketQueueSource q(config);
  CHECK_FALSE(q.is_live());
  constexpr int kPackets = 200;
  std::thread producer([&] {
    const auto data = pattern_payload(1206, 5);
    for (int i = 0; i < kPackets; ++i) q.push(as_bytes(data), i, PacketPort::data);
    q.close();
  });
  PacketView view;
  int received = 0;
  bool in_order = true;
  while (q.next(view, 5000) == SourceStatus::packet) {
    in_order = in_order && view.receive_ns == received;
    ++received;
  }
  producer.join();
  CHECK(received == kPackets);
  CHECK(in_order);
  CHECK(q.counters().queue_full == 0);
}

TEST_CASE("push source: concurrent producers, every packet queued or counted") {
  PushSourceConfig config;
  config.capacity_packets = 16;
  PacketQueueSource q(config);
  constexpr int kPerThread = 500;
  std::atomic<int> queued{0};
  std::vector<std::thread> producers;
  for (int t = 0; t < 3; ++t) {
    producers.emplace_back([&] {
      const auto data = pattern_payload(1206, 6);
      for (int i = 0; i < kPerThread; ++i) {
        if (q.push(as_bytes(data), i, PacketPort::data) == PushResult::queued) ++queued;
      }
    });
  }
  std::thread closer([&] {
    for (auto& p : producers) p.join();
    q.close();
  });
  PacketView view;
  int received = 0;
  while (q.next(view, 5000) == SourceStatus::packet) ++received;
  closer.join();
  CHECK(received == queued.load());
  CHECK(static_cast<std::uint64_t>(received) + q.counters().queue_full == 3u * kPerThread);
}

TEST_CASE("push source: request_stop() ends a blocked next() and refuses pushes") {
  PacketQueueSource q;
  std::thread stopper([&] { q.request_stop(); });
  PacketView view;
  const SourceStatus status = q.next(view, -1);
  stopper.join();
  CHECK(status == SourceStatus::stopped);
  CHECK(q.push(as_bytes(pattern_payload(1206, 1)), 0, PacketPort::data) == PushResult::closed);
}

TEST_CASE("push source: capacity is validated") {
  PushSourceConfig config;
  config.capacity_packets = 1;
  CHECK_THROWS_AS(PacketQueueSource(config), std::invalid_argument);
}
