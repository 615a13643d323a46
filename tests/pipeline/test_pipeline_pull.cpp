// Pull API and frame leases: next() hands out pooled frames; a held lease keeps its frame
// unchanged; when the program holds every frame, live sources drop (counted) and replay waits.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "fake_source.hpp"
#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/pipeline.hpp"

using namespace vlpground;
using test::FakeSource;
using namespace std::chrono_literals;

namespace {

constexpr int kRotations = 14;
constexpr int kPackets = kRotations * FakeSource::kPacketsPerRotation;

PipelineConfig fast_config() {
  PipelineConfig c;
  c.detector.hypotheses = 40;
  return c;
}

std::vector<std::uint64_t> sequences_read_directly(int packets) {
  CaptureReader reader(std::make_unique<FakeSource>(packets, false));
  Frame frame;
  std::vector<std::uint64_t> out;
  while (reader.next(frame) == ReadStatus::frame) out.push_back(frame.meta.sequence);
  return out;
}

// A fingerprint of a frame's contents, to see that a held frame is never rewritten.
double fingerprint(const LabelledFrame& f) {
  double sum = static_cast<double>(f.frame.meta.sequence) * 1e6 + f.frame.columns();
  const auto& range = f.frame.layer[kStrongestLayer].range_m;
  for (int c = 0; c < f.frame.columns(); ++c) sum += range[f.frame.index(3, c)];
  for (std::size_t i = 0; i < f.ground.label[0].size(); i += 7) sum += f.ground.label[0][i];
  return sum;
}

struct Held {
  FrameLease lease;
  double print = 0;
};

}  // namespace

TEST_CASE("pull: next() returns every frame in order, then empty at the end") {
  const auto expected = sequences_read_directly(kPackets);
  Pipeline p(fast_config(), std::make_unique<FakeSource>(kPackets, false));
  CHECK_THROWS_AS(p.next(1ms), std::logic_error);  // before start()
  p.start();
  std::vector<std::uint64_t> got;
  std::uint64_t index = 0;
  bool indices_ok = true;
  while (FrameLease f = p.next(30s)) {
    got.push_back(f->frame.meta.sequence);
    indices_ok = indices_ok && f->delivered_index == index++;
    CHECK(f->ground.columns == f->frame.columns());
  }
  CHECK(p.at_end());
  CHECK(got == expected);
  CHECK(indices_ok);
  CHECK_FALSE(p.next(0ms));
  p.wait();
  const PipelineStats s = p.stats();
  CHECK(s.frames_delivered == expected.size());
  CHECK(s.frames_dropped == 0);
}

TEST_CASE("pull: next() is refused while frames go to a callback") {
  Pipeline p(fast_config(), std::make_unique<FakeSource>(kPackets, false));
  p.on_frame([](const LabelledFrame&) {});
  p.start();
  CHECK_THROWS_AS(p.next(1ms), std::logic_error);
}

TEST_CASE("pull: replay waits while the program holds every frame, nothing dropped") {
  const auto expected = sequences_read_directly(kPackets);
  PipelineConfig c = fast_config();
  c.queue_frames = 2;
  c.lease_frames = 2;  // pool: 2 + 2 + 2 = 6 frames
  Pipeline p(c, std::make_unique<FakeSource>(kPackets, false));
  p.start();
  std::vector<Held> held;
  // Hold every lease: the pool runs dry and next() times out (the reader waits).
  while (FrameLease f = p.next(500ms)) held.push_back({f, fingerprint(*f)});
  CHECK_FALSE(p.at_end());
  REQUIRE(held.size() >= 3);
  CHECK(held.size() <= 6);  // at most the whole pool (the reader waits for a frame)
  CHECK(p.stats().frames_dropped == 0);
  for (const Held& h : held) CHECK(fingerprint(*h.lease) == h.print);  // never rewritten
  std::vector<std::uint64_t> got;
  for (const Held& h : held) got.push_back(h.lease->frame.meta.sequence);
  held.clear();  // the frames go back to the pool: the replay resumes
  while (FrameLease f = p.next(30s)) got.push_back(f->frame.meta.sequence);
  CHECK(p.at_end());
  CHECK(got == expected);
  CHECK(p.stats().frames_dropped == 0);
}

TEST_CASE("pull: live sources drop frames (counted) while the program holds every frame") {
  PipelineConfig c = fast_config();
  c.queue_frames = 2;
  c.lease_frames = 1;  // pool: 5 frames
  Pipeline p(c, std::make_unique<FakeSource>(kPackets, true));
  std::uint64_t drop_reports = 0;
  p.on_diagnostics([&](const Diagnostic& d) {
    if (d.kind == DiagnosticKind::frame_dropped) ++drop_reports;
  });
  p.start();
  std::vector<Held> held;
  while (FrameLease f = p.next(30s)) held.push_back({f, fingerprint(*f)});
  CHECK(p.at_end());
  p.wait();
  const PipelineStats s = p.stats();
  CHECK(s.live);
  CHECK(held.size() <= 4);  // every held frame pins a slot; the reader keeps one
  CHECK(s.frames_delivered == held.size());
  CHECK(s.frames_assembled == s.frames_delivered + s.frames_dropped);
  CHECK(s.frames_dropped >= static_cast<std::uint64_t>(kRotations) - 4);
  CHECK(drop_reports > 0);
  for (const Held& h : held) CHECK(fingerprint(*h.lease) == h.print);
}

TEST_CASE("leases: a callback may keep frames, and a lease outlives the pipeline") {
  std::vector<Held> kept;
  std::uint64_t plain_calls = 0;
  {
    Pipeline p(fast_config(), std::make_unique<FakeSource>(kPackets, false));
    p.on_frame([&](const LabelledFrame&) { ++plain_calls; });
    p.on_frame_lease([&](FrameLease f) {
      if (kept.size() < 2) kept.push_back({f, fingerprint(*f)});  // within lease_frames
    });
    p.start();
    p.wait();
    CHECK(p.stats().frames_delivered == plain_calls);
  }
  REQUIRE(kept.size() == 2);
  CHECK(kept[0].lease->frame.meta.sequence == 0);
  CHECK(kept[1].lease->delivered_index == 1);
  for (const Held& h : kept) CHECK(fingerprint(*h.lease) == h.print);  // pool still alive
}

TEST_CASE("pull: lease_frames is validated") {
  PipelineConfig c;
  c.lease_frames = -1;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
}
