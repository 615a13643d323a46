// Detector speed over the frames of the sim captures: frames are loaded once with
// CaptureReader, then GroundDetector::detect is timed per frame. Counters report the
// per-stage times (ms per frame, averaged), the returns per frame, and the median and 90th
// percentile of the frames' own times in each repetition (frame_median_ms, frame_p90_ms):
// issue 10's limits are per frame, and a median is not moved by a few stalled frames (on
// this VM the slow spells slow every frame alike: docs/detector.md, "Speed").
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "test_data.hpp"
#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/capture_reader.hpp"

using namespace vlpground;

namespace {

std::vector<Frame> load_frames(const std::string& stem) {
  std::vector<Frame> frames;
  const auto path = test::shared_file("sim", stem + ".pcap");
  if (!path) return frames;
  PcapSourceConfig source;
  source.path = path->string();
  CaptureReader reader(open_pcap_source(source));
  Frame f;
  while (reader.next(f) == ReadStatus::frame) {
    if (f.meta.complete) frames.push_back(f);
  }
  return frames;
}

// The q-quantile of v (nearest rank; 0 when empty).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const auto at = static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + at, v.end());
  return v[static_cast<std::size_t>(at)];
}

void bm_detect(benchmark::State& state, const std::string& stem, const std::string& method) {
  static std::vector<std::pair<std::string, std::vector<Frame>>> cache;
  const std::vector<Frame>* frames = nullptr;
  for (const auto& [name, fs] : cache)
    if (name == stem) frames = &fs;
  if (!frames) frames = &cache.emplace_back(stem, load_frames(stem)).second;
  if (frames->empty()) {
    state.SkipWithError("capture not found (set VLPGROUND_SHARED_DIR)");
    return;
  }
  DetectorConfig cfg;
  // "tangent-paper": the paper's method without terrain refinement, "tangent-cells" without
  // the column profiles, for comparison.
  const bool variant = method == "tangent-paper" || method == "tangent-cells";
  cfg.method = variant ? GroundMethod::tangent : *parse_ground_method(method);
  cfg.terrain_refinement = method != "tangent-paper";
  cfg.column_profiles = method == "tangent";
  GroundDetector det(cfg);
  GroundResult result;
  det.detect(frames->front(), result);  // warm-up: sizes every workspace
  StageTimings sum;
  double returns = 0;
  std::size_t k = 0;
  std::vector<double> frame_ms;
  frame_ms.reserve(1u << 16);  // more frames than a repetition times: no allocation while timed
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const Frame& f = (*frames)[k++ % frames->size()];
    const auto start = Clock::now();
    det.detect(f, result);
    const auto stop = Clock::now();
    if (frame_ms.size() < frame_ms.capacity())
      frame_ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
    benchmark::DoNotOptimize(result.ground_returns);
    const StageTimings& t = result.timings;
    sum.cloud_ms += t.cloud_ms;
    sum.tangents_ms += t.tangents_ms;
    sum.hypotheses_ms += t.hypotheses_ms;
    sum.inliers_ms += t.inliers_ms;
    sum.search_ms += t.search_ms;
    sum.labelling_ms += t.labelling_ms;
    returns += static_cast<double>(result.ground_returns + result.obstacle_returns);
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["cloud_ms"] = sum.cloud_ms / n;
  state.counters["tangents_ms"] = sum.tangents_ms / n;
  state.counters["hypotheses_ms"] = sum.hypotheses_ms / n;
  state.counters["inliers_ms"] = sum.inliers_ms / n;
  state.counters["search_ms"] = sum.search_ms / n;
  state.counters["labelling_ms"] = sum.labelling_ms / n;
  state.counters["returns"] = returns / n;
  state.counters["frame_median_ms"] = quantile(frame_ms, 0.5);
  state.counters["frame_p90_ms"] = quantile(frame_ms, 0.9);
}

void register_all() {
  for (const char* stem : {"flat_strongest", "urban_strongest", "slope_strongest", "jam_strongest",
                           "fences_strongest", "flat_dual", "jam_dual", "flat_20hz"}) {
    for (const char* method : {"tangent", "tangent-cells", "tangent-paper", "ransac", "lpr"}) {
      benchmark::RegisterBenchmark((std::string("detect/") + method + "/" + stem).c_str(),
                                   [s = std::string(stem), m = std::string(method)](
                                       benchmark::State& st) { bm_detect(st, s, m); })
          ->Unit(benchmark::kMillisecond)
          ->ComputeStatistics("median",
                              [](const std::vector<double>& v) { return quantile(v, 0.5); });
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
