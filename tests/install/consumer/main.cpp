// A vehicle-software stand-in: links the installed vlpground::pipeline and pulls labelled
// frames with next(), keeping two leases at a time (as an executor holding the previous
// frame for fusion would).
#include <chrono>
#include <cstdio>
#include <vlpground/pipeline.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer FILE.pcap\n");
    return 2;
  }
  vlpground::PcapSourceConfig capture;
  capture.path = argv[1];
  vlpground::PipelineConfig config;
  config.source = capture;
  config.detector.method = vlpground::GroundMethod::tangent;
  vlpground::Pipeline pipeline(config);
  try {
    pipeline.start();
  } catch (const vlpground::Error& e) {
    std::fprintf(stderr, "consumer: %s (%s)\n", e.what(), e.code().message().c_str());
    return 1;
  }
  vlpground::FrameLease previous;
  unsigned frames = 0;
  unsigned long long ground = 0;
  while (vlpground::FrameLease frame = pipeline.next(std::chrono::seconds(10))) {
    if (previous && previous->frame.meta.sequence >= frame->frame.meta.sequence) {
      std::fprintf(stderr, "consumer: frames out of order\n");
      return 1;
    }
    ground += frame->ground.ground_returns;
    ++frames;
    previous = std::move(frame);  // held until the next frame arrives
  }
  if (!pipeline.at_end() || frames == 0 || ground == 0) {
    std::fprintf(stderr, "consumer: %u frames, %llu ground returns, at_end %d\n", frames, ground,
                 pipeline.at_end() ? 1 : 0);
    return 1;
  }
  std::printf("consumer: ok (%u frames, %llu ground returns, last time source %s)\n", frames,
              ground, std::string(vlpground::to_string(previous->frame.meta.time_source)).c_str());
  return 0;
}
