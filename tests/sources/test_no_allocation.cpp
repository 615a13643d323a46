// Steady-state next() must not touch the heap: global operator new is counted in this binary
// while `g_counting` is set.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>

#include "capture_builder.hpp"
#include "test_data.hpp"
#include "vlpground/driver/packet_queue_source.hpp"
#include "vlpground/driver/packet_source.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<int> g_allocations{0};
}  // namespace

namespace {
void* counted_malloc(std::size_t size) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return std::malloc(size == 0 ? 1 : size);
}
}  // namespace

// The whole unaligned family is replaced, so every new/delete pair stays matched (ASan).
void* operator new(std::size_t size) {
  if (void* p = counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return counted_malloc(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return counted_malloc(size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

using namespace vlpground;
using namespace vlpground::test;

namespace {

constexpr int kPackets = 50;

/// Calls next() `count` times with counting on; returns the allocations seen.
int allocations_during(PacketSource& source, int count, std::array<SourceStatus, kPackets>& got) {
  PacketView view;
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < count; ++i) got[static_cast<std::size_t>(i)] = source.next(view, 1000);
  g_counting = false;
  return g_allocations.load();
}

}  // namespace

TEST_CASE("no allocation: pcap replay in steady state") {
  std::vector<Record> records;
  for (int i = 0; i <= kPackets; ++i) {
    records.push_back({1'000'000'000LL + i, ethernet(udp_ipv4(pattern_payload(1206, 1), 2368))});
    records.push_back({1'000'000'000LL + i, ethernet_arp()});
  }
  const auto path = temp_dir("sources_alloc") / "alloc.pcap";
  write_pcap(path, 1, records);
  PcapSourceConfig config;
  config.path = path.string();
  auto source = open_pcap_source(config);
  PacketView view;
  REQUIRE(source->next(view, 0) == SourceStatus::packet);  // warm-up
  std::array<SourceStatus, kPackets> got{};
  CHECK(allocations_during(*source, kPackets, got) == 0);
  for (const SourceStatus s : got) CHECK(s == SourceStatus::packet);
}

TEST_CASE("no allocation: UDP reception in steady state") {
  UdpSourceConfig config;
  config.bind_address = "127.0.0.1";
  config.position_port = 0;
  config.reuse_address = false;
  // Any free port: let the kernel choose for a probe socket, then use it.
  const int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::bind(probe, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
  socklen_t length = sizeof address;
  REQUIRE(::getsockname(probe, reinterpret_cast<sockaddr*>(&address), &length) == 0);
  ::close(probe);
  config.data_port = ntohs(address.sin_port);
  auto source = open_udp_source(config);

  const int sender = ::socket(AF_INET, SOCK_DGRAM, 0);
  const Bytes payload = pattern_payload(1206, 4);
  for (int i = 0; i <= kPackets; ++i) {
    REQUIRE(::sendto(sender, payload.data(), payload.size(), 0,
                     reinterpret_cast<const sockaddr*>(&address), sizeof address) == 1206);
  }
  ::close(sender);
  PacketView view;
  REQUIRE(source->next(view, 1000) == SourceStatus::packet);  // warm-up
  std::array<SourceStatus, kPackets> got{};
  CHECK(allocations_during(*source, kPackets, got) == 0);
  for (const SourceStatus s : got) CHECK(s == SourceStatus::packet);
}

TEST_CASE("no allocation: push source, push and next in steady state") {
  PushSourceConfig config;
  config.capacity_packets = 8;
  PacketQueueSource q(config);
  const Bytes payload = pattern_payload(1206, 5);
  const auto bytes = std::as_bytes(std::span<const std::uint8_t>(payload));
  PacketView view;
  REQUIRE(q.push(bytes, 0, PacketPort::data) == PushResult::queued);  // warm-up
  REQUIRE(q.next(view, 0) == SourceStatus::packet);
  int failures = 0;
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < kPackets; ++i) {
    failures += q.push(bytes, i, PacketPort::data) == PushResult::queued ? 0 : 1;
    failures += q.next(view, 0) == SourceStatus::packet ? 0 : 1;
  }
  g_counting = false;
  CHECK(g_allocations.load() == 0);
  CHECK(failures == 0);
}
