// Counts every heap allocation of the process (replaced global operator new) to check that
// the pipeline allocates nothing per frame once warm.
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>

#include "fake_source.hpp"
#include "vlpground/pipeline.hpp"

namespace {
std::atomic<std::uint64_t> g_allocations{0};
}

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace vlpground;

TEST_CASE("no heap allocation per frame in steady state (replay)") {
  constexpr int kRotations = 14;
  PipelineConfig c;
  c.detector.hypotheses = 40;
  Pipeline p(c, std::make_unique<test::FakeSource>(kRotations * 76, false));
  constexpr std::uint64_t kWarmup = 4;
  std::uint64_t at_warm = 0, at_last = 0, frames = 0;
  p.on_frame([&](const LabelledFrame& f) {
    ++frames;
    if (!f.frame.meta.complete) return;  // the final flush is not steady state
    if (f.delivered_index == kWarmup) at_warm = g_allocations.load();
    if (f.delivered_index > kWarmup) at_last = g_allocations.load();
  });
  p.start();
  p.wait();
  REQUIRE(frames > kWarmup + 4);
  CHECK(at_last - at_warm == 0);
}

TEST_CASE("no heap allocation per frame in steady state (pull API, leases held)") {
  constexpr int kRotations = 16;
  PipelineConfig c;
  c.detector.hypotheses = 40;
  c.lease_frames = 3;
  Pipeline p(c, std::make_unique<test::FakeSource>(kRotations * 76, false));
  p.start();
  // A program keeping the latest three frames (a sliding window of leases).
  FrameLease window[3];
  constexpr std::uint64_t kWarmup = 6;  // every pool slot used once
  std::uint64_t frames = 0, at_warm = 0, at_last = 0;
  while (FrameLease f = p.next(std::chrono::seconds(30))) {
    if (!f->frame.meta.complete) continue;
    if (f->delivered_index == kWarmup) at_warm = g_allocations.load();
    if (f->delivered_index > kWarmup) at_last = g_allocations.load();
    window[frames++ % 3] = std::move(f);
  }
  REQUIRE(frames > kWarmup + 4);
  CHECK(at_last - at_warm == 0);
}
