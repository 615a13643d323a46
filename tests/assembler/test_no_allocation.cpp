// Steady-state decoding + assembling performs no heap allocation: global operator new is
// replaced by a counting version for this executable only.
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>

#include "encoded_stream.hpp"
#include "memory_source.hpp"
#include "vlpground/driver/capture_reader.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace vlpground;

namespace {

constexpr std::int64_t kHourStartNs = 1'699'999'200'000'000'000;  // a top of the hour

std::vector<test::MemorySource::Packet> as_source_packets(
    const std::vector<test::PacketBytes>& bytes, std::int64_t period_ns) {
  std::vector<test::MemorySource::Packet> out;
  std::int64_t t = kHourStartNs + 1'000'000'000;
  for (const auto& b : bytes) {
    out.push_back({std::vector<std::uint8_t>(b.begin(), b.end()), PacketKind::data, t});
    t += period_ns;
  }
  return out;
}

}  // namespace

TEST_CASE("decode + assemble allocates nothing in steady state", "[assembler][alloc]") {
  const auto mode = GENERATE(ReturnMode::strongest, ReturnMode::dual);
  const std::int64_t period =
      mode == ReturnMode::dual ? kDualPacketPeriodNs : kSinglePacketPeriodNs;
  const auto packets = test::encode_stream(6000, 600, mode);
  PacketDecoder decoder;
  RotationAssembler assembler;
  DecodedPacket decoded;
  Frame out;
  int frames = 0;
  auto run = [&](std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i) {
      const std::int64_t receive =
          kHourStartNs + 1'000'000'000 + static_cast<std::int64_t>(i) * period;
      if (decoder.decode(packets[i], receive, decoded) != DecodeStatus::ok) continue;
      if (assembler.push(decoded, out)) ++frames;
      while (assembler.pop(out)) ++frames;
    }
  };
  run(0, 500);  // warm-up: first frames, spare frames swapped through
  const int warm_frames = frames;
  g_allocations = 0;
  run(500, packets.size());
  const long allocations = g_allocations.load();
  CHECK(allocations == 0);
  CHECK(frames - warm_frames >= 3);  // the measured part did complete frames
  CHECK(decoder.counters().decoded == packets.size());
}

TEST_CASE("CaptureReader::next allocates nothing in steady state", "[assembler][alloc]") {
  const auto bytes = test::encode_stream(4000, 600, ReturnMode::strongest);
  CaptureReader reader(
      std::make_unique<test::MemorySource>(as_source_packets(bytes, kSinglePacketPeriodNs)));
  Frame out;
  REQUIRE(reader.next(out) == ReadStatus::frame);  // warm-up
  REQUIRE(reader.next(out) == ReadStatus::frame);
  g_allocations = 0;
  int frames = 0;
  while (reader.next(out) == ReadStatus::frame) ++frames;
  const long allocations = g_allocations.load();
  CHECK(allocations == 0);
  CHECK(frames >= 3);
  CHECK(reader.counters().assembler.packets_used == bytes.size());
}
