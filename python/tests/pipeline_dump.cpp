// Test helper: replays a capture through vlpground::Pipeline with default settings and prints
// one JSON object per delivered frame (its metadata and label counts), so the Python tests
// can compare frame by frame with what the C++ pipeline delivers.
//   vlpground_pipeline_dump FILE.pcap
#include <cstdio>
#include <exception>

#include "vlpground/pipeline.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: vlpground_pipeline_dump FILE.pcap\n");
    return 2;
  }
  try {
    vlpground::PipelineConfig config;
    vlpground::PcapSourceConfig pcap;
    pcap.path = argv[1];
    config.pcap = pcap;
    vlpground::Pipeline pipeline(config);
    pipeline.on_frame([](const vlpground::LabelledFrame& f) {
      const vlpground::FrameMeta& m = f.frame.meta;
      unsigned long long returns = 0;
      for (int l = 0; l < f.frame.layers(); ++l) {
        for (int r = 0; r < vlpground::kLasers; ++r) {
          for (int c = 0; c < f.frame.columns(); ++c) returns += f.frame.layer[l].valid[f.frame.index(r, c)];
        }
      }
      std::printf(
          "{\"sequence\": %llu, \"columns\": %d, \"complete\": %s, \"start_time_ns\": %lld, "
          "\"end_time_ns\": %lld, \"packets_used\": %u, \"packets_lost\": %u, "
          "\"packets_skipped\": %u, \"columns_lost\": %u, \"columns_outside_fov\": %u, "
          "\"returns\": %llu, \"ground_returns\": %llu, \"obstacle_returns\": %llu}\n",
          static_cast<unsigned long long>(m.sequence), f.frame.columns(),
          m.complete ? "true" : "false", static_cast<long long>(m.first_time_ns),
          static_cast<long long>(m.last_time_ns), m.packets_used, m.packets_lost,
          m.packets_skipped, m.columns_lost, m.columns_outside_fov, returns,
          static_cast<unsigned long long>(f.ground.ground_returns),
          static_cast<unsigned long long>(f.ground.obstacle_returns));
    });
    pipeline.start();
    pipeline.wait();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground_pipeline_dump: %s\n", e.what());
    return 1;
  }
  return 0;
}
