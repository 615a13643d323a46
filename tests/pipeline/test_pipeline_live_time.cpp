// Live time base on loopback UDP: the simulator's emitter plays a capture whose GPS date
// (2023) is years off the host clock. The first GPS hour reference arrives mid-rotation; the
// rotation must not be split (the assembler moves it to the GPS clock), and the frame stamps
// on each clock are continuous from the first frame.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <thread>
#include <vector>

#include "loopback.hpp"
#include "vlpground/pipeline.hpp"
#include "vlpground/sim/simulator.hpp"
#include "vlpground/sim/udp_emitter.hpp"

using namespace vlpground;

TEST_CASE("live: the first GPS reference does not split a rotation, stamps stay continuous",
          "[pipeline][udp][time]") {
  sim::SimConfig s;
  s.scene = sim::SceneKind::flat;
  s.frames = 4;
  const sim::Simulator simulator(s);

  const auto [data_port, position_port] = test::free_port_pair();
  UdpSourceConfig udp;
  udp.bind_address = "127.0.0.1";
  udp.data_port = data_port;
  udp.position_port = position_port;
  PipelineConfig config;
  config.source = udp;
  config.detector.hypotheses = 40;
  config.backpressure = Backpressure::block;  // nothing dropped: every frame is checked
  Pipeline pipeline(config);
  pipeline.start();

  sim::UdpStreamConfig emit;
  emit.data_port = data_port;
  emit.position_port = position_port;
  emit.rate = 2.0;
  sim::UdpStreamStats sent;
  std::thread emitter([&] { sent = sim::stream_udp(simulator, emit); });

  std::vector<FrameMeta> frames;
  // Bounded: the emitter needs ~0.25 s; a 2 s pause after it means the input has ended.
  while (FrameLease f = pipeline.next(std::chrono::seconds(2))) frames.push_back(f->frame.meta);
  emitter.join();
  pipeline.stop();
  const PipelineStats stats = pipeline.stats();

  REQUIRE(sent.data_packets == simulator.packet_count());
  REQUIRE(stats.capture.source.kernel_drops == 0);
  REQUIRE(stats.capture.source.data_packets == sent.data_packets);
  CHECK(stats.capture.assembler.clock_rebases == 1);   // host clock -> GPS clock, once
  CHECK(stats.capture.assembler.stream_changes == 0);  // no split at the switch
  CHECK(stats.capture.assembler.packets_lost == 0);
  REQUIRE(frames.size() >= 5);
  // The partial start, s.frames complete rotations, the partial end (silence).
  int complete = 0;
  for (const FrameMeta& m : frames) complete += m.complete ? 1 : 0;
  CHECK(complete == s.frames);
  for (std::size_t i = 1; i + 1 < frames.size(); ++i) {
    INFO("frame " << i);
    CHECK(frames[i].complete);
    CHECK(frames[i].end == FrameEnd::cut);
  }
  // The reference comes with the first position packet, after 14 data packets: frames
  // before it (at most the partial start) are on the host clock, every later one on GPS.
  std::size_t first_gps = 0;
  while (first_gps < frames.size() && frames[first_gps].time_source != TimeSource::gps_pps) {
    CHECK(frames[first_gps].time_source == TimeSource::host_clock);
    ++first_gps;
  }
  CHECK(first_gps <= 1);
  for (std::size_t i = first_gps; i < frames.size(); ++i) {
    CHECK(frames[i].time_source == TimeSource::gps_pps);
  }
  if (first_gps == 0) {  // the GPS clock from the first firing on (sim start: 22:00:01 UTC)
    CHECK(std::abs(frames.front().first_time_ns - s.start_utc_ns) < 1'000'000);
  }
  // Continuous on each clock: a frame starts where the previous one ended (one sequence).
  for (std::size_t i = first_gps + 1; i < frames.size(); ++i) {
    INFO("frame " << i);
    const std::int64_t gap = frames[i].first_time_ns - frames[i - 1].last_time_ns;
    CHECK(gap > 0);
    CHECK(gap <= 55'296);
  }
}
