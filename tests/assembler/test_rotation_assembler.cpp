// Rotation assembler on synthetic decoded packets: seam, N per rotation, dual layers, loss,
// duplicates/reordering, rpm change, silence, capacity, FOV sectors.
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "assembler_harness.hpp"

using namespace vlpground;
using vlpground::test::AssemblerHarness;
using vlpground::test::SyntheticStream;

namespace {

constexpr std::int64_t kSecondNs = 1'000'000'000;

double forward(double from, double to) {
  double d = std::fmod(to - from, 360.0);
  return d < 0 ? d + 360.0 : d;
}

// Sequences in one rotation at `rpm`, from the firing period alone.
double sequences_per_rotation(double rpm) {
  return 60.0 / rpm * 1e9 / static_cast<double>(kSequencePeriodNs);
}

void run(AssemblerHarness& h, SyntheticStream& s, int packets) {
  DecodedPacket p;
  for (int i = 0; i < packets; ++i) {
    s.next(p);
    h.push(p);
  }
}

int packets_for(double rotations, double rpm, ReturnMode mode) {
  const double per_packet = mode == ReturnMode::dual ? 12.0 : 24.0;
  return static_cast<int>(rotations * sequences_per_rotation(rpm) / per_packet);
}

// Each frame after the first starts with the first column at/after the cut.
void check_seams(const AssemblerHarness& h, double cut_deg) {
  for (std::size_t f = 1; f < h.frames.size(); ++f) {
    if (!h.metas[f].complete && h.metas[f - 1].end != FrameEnd::cut) continue;
    const auto& prev = h.frames[f - 1].back();
    const auto& first = h.frames[f].front();
    INFO("frame " << f << " prev az " << prev.azimuth_deg << " first az " << first.azimuth_deg);
    CHECK(forward(cut_deg, first.azimuth_deg) < forward(prev.azimuth_deg, first.azimuth_deg));
  }
}

}  // namespace

TEST_CASE("every firing lands in exactly one frame, cut at the firing", "[assembler]") {
  const double cut = GENERATE(0.0, 90.0, 359.95);
  AssemblerConfig config;
  config.cut_angle_deg = cut;
  AssemblerHarness h(config);
  SyntheticStream s(600, ReturnMode::strongest);
  run(h, s, packets_for(12.3, 600, ReturnMode::strongest));
  h.flush();

  REQUIRE(h.emitted_valid() == h.sent);
  // Expected frames from the stream itself: one more than the cut crossings.
  std::size_t crossings = 0;
  for (std::size_t i = 1; i < h.sent.size(); ++i) {
    const double a = h.sent[i - 1].azimuth_deg, b = h.sent[i].azimuth_deg;
    if (forward(cut, b) < forward(a, b)) ++crossings;
  }
  REQUIRE(crossings >= 11);
  REQUIRE(h.frames.size() == crossings + 1);  // leading partial, complete ones, trailing partial
  CHECK_FALSE(h.metas.front().complete);
  CHECK_FALSE(h.metas.back().complete);
  CHECK(h.metas.back().end == FrameEnd::end_of_input);
  int cuts_inside_packet = 0;
  for (std::size_t f = 1; f + 1 < h.frames.size(); ++f) {
    CHECK(h.metas[f].complete);
    CHECK(h.metas[f].sequence == f);
    if (h.frames[f].front().in_packet != 0) ++cuts_inside_packet;
  }
  CHECK(cuts_inside_packet >= 10);  // the seam falls inside packets, not at their edges
  check_seams(h, cut);
  CHECK(h.assembler.counters().packets_used == h.sent.size() / 24);
  CHECK(h.assembler.counters().packets_lost == 0);
}

TEST_CASE("columns per rotation follow the measured rpm", "[assembler]") {
  const double rpm = GENERATE(600.0, 1200.0, 300.0);
  const auto mode = GENERATE(ReturnMode::strongest, ReturnMode::dual);
  AssemblerHarness h;
  SyntheticStream s(rpm, mode);
  run(h, s, packets_for(4.5, rpm, mode));
  const double n = sequences_per_rotation(rpm);
  int complete = 0;
  for (std::size_t f = 0; f < h.frames.size(); ++f) {
    if (!h.metas[f].complete) continue;
    ++complete;
    const auto cols = static_cast<double>(h.frames[f].size());
    CHECK(cols >= std::floor(n));
    CHECK(cols <= std::ceil(n));
    CHECK(h.metas[f].rpm == Approx(rpm).epsilon(0.002));
    CHECK(h.metas[f].mode == mode);
    CHECK(h.metas[f].last_time_ns == h.frames[f].back().time_ns + 15 * kFiringIntervalNs);
  }
  CHECK(complete == 3);
}

TEST_CASE("cells are placed by ring and carry both layers in dual mode", "[assembler]") {
  const auto mode = GENERATE(ReturnMode::strongest, ReturnMode::dual);
  RotationAssembler assembler;
  Frame out;
  SyntheticStream s(600, mode, 10.0);
  DecodedPacket p;
  bool got = false;
  const std::int64_t t0 = 1'700'000'000'000'000'000;
  while (!got) {
    s.next(p);
    got = assembler.push(p, out);
  }
  REQUIRE(out.layers() == (mode == ReturnMode::dual ? 2 : 1));
  // Rows bottom-up: the manual's ring order.
  for (int ring = 0; ring < kLasers; ++ring) {
    CHECK(out.laser_of_ring[ring] == (ring < 8 ? 2 * ring : 2 * (ring - 8) + 1));
  }
  for (int col = 0; col < out.columns(); col += 7) {
    const auto c = static_cast<std::size_t>(col);
    const auto global =
        static_cast<std::uint64_t>((out.column_time_ns[c] - t0) / kSequencePeriodNs);
    for (int ring = 0; ring < kLasers; ++ring) {
      const int laser = out.laser_of_ring[ring];
      const auto i = out.index(ring, col);
      for (int layer = 0; layer < out.layers(); ++layer) {
        const float d = SyntheticStream::distance_of(global, laser, layer);
        CHECK(out.layer[layer].range_m[i] == d);
        CHECK(out.layer[layer].valid[i] == (d > 0.f ? 1 : 0));
        CHECK(out.layer[layer].intensity[i] == laser * 10 + layer);
        CHECK(out.layer[layer].time_offset_us[i] ==
              Approx(static_cast<double>(out.column_time_ns[c] - out.meta.first_time_ns) * 1e-3 +
                     2.304 * laser));
      }
      if (mode == ReturnMode::dual) {
        CHECK(out.same_echo[i] == (static_cast<std::uint64_t>(laser) + global) % 2);
      }
    }
  }
  CHECK(out.meta.first_time_ns == out.column_time_ns[0]);
}

TEST_CASE("lost packets become invalid columns at their place", "[assembler]") {
  const auto mode = GENERATE(ReturnMode::strongest, ReturnMode::dual);
  const int per_packet = mode == ReturnMode::dual ? 12 : 24;
  AssemblerHarness h;
  SyntheticStream s(600, mode, 200.0);
  run(h, s, 100 * 24 / per_packet);  // past the first cut, inside the 2nd frame
  const std::int64_t lost_from = h.sent.back().time_ns + kSequencePeriodNs;
  s.skip(3);
  run(h, s, packets_for(2.0, 600, mode));
  h.flush();

  CHECK(h.assembler.counters().packets_lost == 3);
  CHECK(h.assembler.counters().columns_lost == static_cast<std::uint64_t>(3 * per_packet));
  CHECK(h.emitted_valid() == h.sent);
  REQUIRE(h.metas.size() >= 2);
  const auto& frame = h.frames[1];
  CHECK(h.metas[1].complete);
  CHECK(h.metas[1].packets_lost == 3);
  CHECK(h.metas[1].columns_lost == static_cast<std::uint32_t>(3 * per_packet));
  const double n = sequences_per_rotation(600);
  CHECK(static_cast<double>(frame.size()) >= std::floor(n));
  CHECK(static_cast<double>(frame.size()) <= std::ceil(n));
  int invalid = 0;
  for (std::size_t c = 0; c < frame.size(); ++c) {
    if (frame[c].valid) continue;
    // On the firing grid, right after the last received column, azimuth interpolated.
    CHECK(frame[c].time_ns == lost_from + invalid * kSequencePeriodNs);
    CHECK(frame[c].packet_index == kNoPacketIndex);
    CHECK(forward(frame[c - 1].azimuth_deg, frame[c].azimuth_deg) ==
          Approx(forward(frame[c - 1].azimuth_deg, frame[c + 1].azimuth_deg) / 2).margin(0.2));
    ++invalid;
  }
  CHECK(invalid == 3 * per_packet);
}

TEST_CASE("a gap wider than max_gap_fill_deg ends the frame instead of filling", "[assembler]") {
  AssemblerHarness h;
  SyntheticStream s(600, ReturnMode::strongest, 100.0);
  run(h, s, 120);
  s.skip(45);  // ~216 degrees
  run(h, s, 200);
  h.flush();
  REQUIRE(h.metas.size() >= 3);
  CHECK(h.metas[1].end == FrameEnd::gap);
  CHECK_FALSE(h.metas[1].complete);
  CHECK(h.metas[1].packets_lost == 45);
  CHECK(h.assembler.counters().columns_lost == 0);
  CHECK(h.assembler.counters().large_gaps == 1);
  CHECK(h.emitted_valid() == h.sent);
}

TEST_CASE("duplicates and reordered packets are counted and dropped", "[assembler]") {
  AssemblerHarness h;
  SyntheticStream s(600, ReturnMode::strongest);
  DecodedPacket p, older;
  run(h, s, 10);
  s.next(older);
  h.push(older);
  s.next(p);
  h.push(p);
  h.push(p, -1, true);      // duplicate
  h.push(older, -1, true);  // reordered
  run(h, s, 200);
  h.flush();
  const auto& c = h.assembler.counters();
  CHECK(c.duplicate_packets == 1);
  CHECK(c.reordered_packets == 1);
  CHECK(c.packets_skipped() == 2);
  CHECK(c.packets_used == 212);
  CHECK(h.metas[0].packets_skipped + h.metas[1].packets_skipped == 2);
  CHECK(h.emitted_valid() == h.sent);
}

TEST_CASE("motor speed changes mid-stream change N", "[assembler]") {
  AssemblerHarness h;
  SyntheticStream s(600, ReturnMode::strongest);
  run(h, s, packets_for(2.5, 600, ReturnMode::strongest));
  s.set_rpm(900);
  run(h, s, packets_for(3.5, 900, ReturnMode::strongest));
  h.flush();
  CHECK(h.emitted_valid() == h.sent);
  const auto& last_complete = h.metas[h.metas.size() - 2];
  REQUIRE(last_complete.complete);
  CHECK(last_complete.rpm == Approx(900).epsilon(0.002));
  const double n = sequences_per_rotation(900);
  const auto cols = static_cast<double>(h.frames[h.frames.size() - 2].size());
  CHECK(cols >= std::floor(n));
  CHECK(cols <= std::ceil(n));
  CHECK(h.assembler.counters().packets_lost == 0);
}

TEST_CASE("silence ends the frame in progress as incomplete", "[assembler]") {
  SECTION("seen in the packet stamps") {
    AssemblerHarness h;
    SyntheticStream s(600, ReturnMode::strongest);
    run(h, s, 100);
    s.skip(200);  // 265 ms
    run(h, s, 10);
    REQUIRE(h.metas.size() == 2);
    CHECK(h.metas[1].end == FrameEnd::silence);
    CHECK_FALSE(h.metas[1].complete);
    CHECK(h.assembler.counters().silences == 1);
    CHECK(h.assembler.counters().columns_lost == 0);
  }
  SECTION("seen on the steady clock") {
    AssemblerHarness h;
    SyntheticStream s(600, ReturnMode::strongest);
    DecodedPacket p;
    std::int64_t steady = 5 * kSecondNs;
    for (int i = 0; i < 100; ++i) {
      s.next(p);
      steady += kSinglePacketPeriodNs;
      h.push(p, steady);
    }
    const auto before = h.metas.size();
    h.expire(steady + 150'000'000);  // shorter than the 200 ms timeout
    CHECK(h.metas.size() == before);
    h.expire(steady + 250'000'000);
    REQUIRE(h.metas.size() == before + 1);
    CHECK(h.metas.back().end == FrameEnd::silence);
    CHECK_FALSE(h.metas.back().complete);
    CHECK(h.metas.back().completed_receive_ns == steady);
    run(h, s, 100);  // the stream resumes: a new partial frame, nothing lost or duplicated
    h.flush();
    CHECK(h.emitted_valid() == h.sent);
  }
}

TEST_CASE("a full frame ends as incomplete and the next column starts a new one", "[assembler]") {
  AssemblerConfig config;
  config.capacity_columns = 1000;
  AssemblerHarness h(config);
  SyntheticStream s(600, ReturnMode::strongest);
  run(h, s, 300);
  h.flush();
  CHECK(h.assembler.counters().capacity_overflows >= 3);
  for (std::size_t f = 0; f < h.frames.size(); ++f) {
    CHECK(h.frames[f].size() <= 1000);
    if (h.metas[f].end == FrameEnd::capacity) CHECK_FALSE(h.metas[f].complete);
  }
  CHECK(h.emitted_valid() == h.sent);
}

TEST_CASE("a FOV-restricted sensor gives complete frames with columns outside the FOV",
          "[assembler]") {
  // The sensor sends only while the azimuth is in [90, 270): packets keep their period.
  AssemblerHarness h;
  SyntheticStream s(600, ReturnMode::strongest, 95.0);
  DecodedPacket p;
  for (int i = 0; i < packets_for(6.0, 600, ReturnMode::strongest); ++i) {
    s.next(p);
    const double az = p.azimuth(0, 0);
    if (az >= 90.0 && az < 270.0) h.push(p);
  }
  h.flush();
  CHECK(h.emitted_valid() == h.sent);
  // The first silent sector is taken for loss (too wide to fill); later ones are recognised.
  CHECK(h.assembler.counters().large_gaps == 1);
  CHECK(h.assembler.counters().packets_lost == 38);
  int complete = 0;
  for (std::size_t f = 0; f < h.metas.size(); ++f) {
    if (!h.metas[f].complete) continue;
    ++complete;
    CHECK(h.metas[f].columns_lost == 0);
    CHECK(h.metas[f].columns_outside_fov > 850);
    CHECK(h.metas[f].rpm == Approx(600).epsilon(0.01));
  }
  CHECK(complete >= 3);
}

TEST_CASE("assembler config is validated", "[assembler]") {
  AssemblerConfig c;
  CHECK_NOTHROW(c.validate());
  c.cut_angle_deg = 360.0;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
  c = {};
  c.capacity_columns = 10;
  CHECK_THROWS_AS(RotationAssembler(c), std::invalid_argument);
  c = {};
  c.silence_timeout_ms = 0;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
}

TEST_CASE("discard_frame throws away the frame in progress and accounts for its packets",
          "[assembler]") {
  AssemblerHarness h;
  SyntheticStream s(600, ReturnMode::strongest, 10.0);
  DecodedPacket p;
  const int before = 5;  // well inside the first rotation: no frame completes
  for (int i = 0; i < before; ++i) {
    s.next(p);
    h.assembler.push(p, h.out);
  }
  h.assembler.discard_frame();
  CHECK(h.assembler.counters().packets_used == 0);
  CHECK(h.assembler.counters().discarded_packets == before);
  // The stream restarts: later packets form frames of their own, none holding the discarded.
  const int after = packets_for(1.5, 600, ReturnMode::strongest);
  for (int i = 0; i < after; ++i) {
    s.next(p);
    h.push(p);
  }
  h.flush();
  CHECK(h.emitted_valid() == h.sent);
  CHECK(h.assembler.counters().packets_used == static_cast<std::uint64_t>(after));
  CHECK(h.assembler.counters().packets_skipped() == static_cast<std::uint64_t>(before));
  std::uint64_t skipped_in_frames = 0;
  for (const auto& m : h.metas) skipped_in_frames += m.packets_skipped;
  CHECK(skipped_in_frames == static_cast<std::uint64_t>(before));
}

TEST_CASE("a re-based clock moves the frame in progress instead of splitting it", "[assembler]") {
  AssemblerHarness h;
  SyntheticStream s(600, ReturnMode::strongest, 10.0);
  DecodedPacket p;
  const std::int64_t shift = -7 * 3'600'000'000'000;  // host clock to GPS clock
  const int total = packets_for(2.5, 600, ReturnMode::strongest);
  const int switch_at = 20;  // inside the first partial rotation
  for (int i = 0; i < total; ++i) {
    s.next(p);
    if (i >= switch_at) {
      p.time_ns += shift;
      for (int c = 0; c < p.column_count; ++c)
        p.column_time_ns[static_cast<std::size_t>(c)] += shift;
    }
    p.time_rebase_ns = i == switch_at ? shift : 0;
    h.push(p);
  }
  h.flush();
  CHECK(h.assembler.counters().clock_rebases == 1);
  CHECK(h.assembler.counters().stream_changes == 0);
  CHECK(h.assembler.counters().silences == 0);
  REQUIRE(h.metas.size() == 3);  // partial, complete, partial: no extra split
  CHECK(h.metas[1].complete);
  // Every frame is on the new clock, columns included, and time runs forward within it.
  for (std::size_t f = 0; f < h.frames.size(); ++f) {
    const auto& cols = h.frames[f];
    CHECK(h.metas[f].first_time_ns == cols.front().time_ns);
    for (std::size_t c = 1; c < cols.size(); ++c) CHECK(cols[c].time_ns > cols[c - 1].time_ns);
  }
}
