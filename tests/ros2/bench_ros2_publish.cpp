// Time the frame callback spends in Ros2Publisher::publish() (what publishing adds per frame
// to the detection thread), next to the PointCloud2 encoding alone. Frames are synthetic,
// 1808 columns (one rotation at 600 rpm), labelled. DDS stays on loopback (dds_loopback.cpp).
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "../outputs/labelled_frame.hpp"
#include "cloud_reader.hpp"
#include "dds_loopback.hpp"
#include "vlpground/outputs/pointcloud2.hpp"
#include "vlpground/ros2/publisher.hpp"

using namespace vlpground;

namespace {

constexpr int kColumns = 1808;

ReturnMode mode_of(const benchmark::State& state) {
  return state.range(0) == 2 ? ReturnMode::dual : ReturnMode::strongest;
}

void BM_EncodeOrganized(benchmark::State& state) {
  test::LabelledTestFrame in(kColumns, mode_of(state), 0);
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame));
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        outputs::encode_pointcloud2(in.frame, in.ground, outputs::CloudKind::organized, data));
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(data.size()));
}
BENCHMARK(BM_EncodeOrganized)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

// publish() with the given subscriber situation; range(1): 0 no subscriber, 1 a reliable
// subscriber that never takes its samples (a stalled reader), 2 a reader taking every sample.
void BM_Publish(benchmark::State& state, bool all_topics) {
  ros2::Ros2Config config;
  config.domain_id = test::confine_dds_to_loopback();
  config.topic = "/bench/points";
  if (all_topics) {
    config.ground_topic = "/bench/ground";
    config.obstacle_topic = "/bench/obstacles";
  }
  ros2::Ros2Publisher publisher(config);
  std::unique_ptr<test::CloudReader> reader;
  if (state.range(1) > 0) {
    const int max_samples = state.range(1) == 1 ? 2 : 0;
    reader = std::make_unique<test::CloudReader>(config.domain_id, "rt/bench/points",
                                                 test::ReaderQos::reliable, max_samples);
    if (!publisher.wait_for_subscribers(1, 10000)) state.SkipWithError("no match");
  }
  test::LabelledTestFrame in(kColumns, mode_of(state), 0);
  publisher.publish(in.frame, in.ground);  // warm-up
  test::ReceivedCloud cloud;
  for (auto _ : state) {
    publisher.publish(in.frame, in.ground);
    if (state.range(1) == 2) {
      state.PauseTiming();
      reader->take(cloud, 1000);
      state.ResumeTiming();
    }
  }
  publisher.finish(1000);
  const auto stats = publisher.stats();
  state.counters["skipped_share"] =
      static_cast<double>(stats.frames_skipped) / static_cast<double>(stats.frames_offered);
}
void BM_PublishPoints(benchmark::State& state) { BM_Publish(state, false); }
void BM_PublishAllTopics(benchmark::State& state) { BM_Publish(state, true); }
BENCHMARK(BM_PublishPoints)
    ->ArgsProduct({{1, 2}, {0, 1, 2}})
    ->ArgNames({"returns", "subscriber"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PublishAllTopics)
    ->ArgsProduct({{1}, {0, 1}})
    ->ArgNames({"returns", "subscriber"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
