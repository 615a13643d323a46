// Embedding vlpground: replay a capture, get every labelled rotation in a callback.
#include <cstdio>

#include "vlpground/pipeline.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: embed FILE.pcap\n");
    return 2;
  }
  vlpground::PcapSourceConfig capture;
  capture.path = argv[1];
  vlpground::PipelineConfig config;
  config.source = capture;
  config.detector.method = vlpground::GroundMethod::tangent;
  vlpground::Pipeline pipeline(config);
  pipeline.on_frame([](const vlpground::LabelledFrame& f) {
    std::printf("frame %llu: %d columns, %llu ground returns\n",
                static_cast<unsigned long long>(f.frame.meta.sequence), f.frame.columns(),
                static_cast<unsigned long long>(f.ground.ground_returns));
  });
  pipeline.start();  // throws std::runtime_error when the file cannot be opened
  pipeline.wait();
  const vlpground::PipelineStats s = pipeline.stats();
  std::printf("%llu frames, latency p99 %.2f ms\n",
              static_cast<unsigned long long>(s.frames_delivered), s.latency.p99_ms);
}
