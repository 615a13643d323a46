// Embedding vlpground with the pull API: a cyclic task asks for the newest labelled rotation
// when it runs, keeps the previous one (a lease, no copy) to compare ground heights, and
// feeds packets that arrive through its own middleware into a push source.
//
//   vlpground_pull_example FILE.pcap          frames from a capture (the pipeline reads it)
//   vlpground_pull_example --push FILE.pcap   the program reads the capture and push()es
//                                             every packet, as a bag player would
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include "vlpground/driver/packet_queue_source.hpp"
#include "vlpground/pipeline.hpp"

namespace {

// The ground share of a frame: labelled-ground returns over all labelled returns.
double ground_share(const vlpground::LabelledFrame& f) {
  const auto all = f.ground.ground_returns + f.ground.obstacle_returns;
  return all == 0 ? 0.0 : static_cast<double>(f.ground.ground_returns) / static_cast<double>(all);
}

// Stands in for middleware delivering packets: reads a capture and pushes each payload.
void play_into(vlpground::PacketQueueSource& queue, const std::string& path) {
  vlpground::PcapSourceConfig capture;
  capture.path = path;
  const auto source = vlpground::open_pcap_source(capture);
  vlpground::PacketView packet;
  while (source->next(packet, 0) == vlpground::SourceStatus::packet) {
    queue.push(std::as_bytes(packet.bytes), packet.receive_ns, packet.kind, packet.source);
  }
  queue.close();  // end of input: next() returns empty once every frame was handed out
}

}  // namespace

int main(int argc, char** argv) {
  const bool push = argc == 3 && std::strcmp(argv[1], "--push") == 0;
  if (argc != 2 && !push) {
    std::fprintf(stderr, "usage: vlpground_pull_example [--push] FILE.pcap\n");
    return 2;
  }
  const std::string path = argv[argc - 1];
  vlpground::PipelineConfig config;
  if (push) {
    vlpground::PushSourceConfig queue;
    queue.block_when_full = true;  // a recording: wait rather than lose packets
    config.source = queue;
  } else {
    vlpground::PcapSourceConfig capture;
    capture.path = path;
    config.source = capture;
  }
  vlpground::Pipeline pipeline(config);
  try {
    pipeline.start();  // vlpground::Error (with an ErrorCode) when the source cannot open
  } catch (const vlpground::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  std::thread player;
  if (push) player = std::thread([&] { play_into(pipeline.packet_queue(), path); });

  vlpground::FrameLease previous;  // kept across cycles: the frame stays valid and unchanged
  while (!pipeline.at_end()) {
    const vlpground::FrameLease frame = pipeline.next(std::chrono::milliseconds(100));
    if (!frame) continue;  // nothing new this cycle
    const auto& meta = frame->frame.meta;
    std::printf("frame %llu: %d columns, ground %.1f %%, detect %.2f ms, time %s",
                static_cast<unsigned long long>(meta.sequence), frame->frame.columns(),
                100.0 * ground_share(*frame), frame->timings.detect_ms,
                std::string(vlpground::to_string(meta.time_source)).c_str());
    if (previous) {
      std::printf(", %.1f ms after the previous frame",
                  static_cast<double>(meta.first_time_ns - previous->frame.meta.first_time_ns) *
                      1e-6);
    }
    std::printf("\n");
    previous = frame;  // the older lease goes: its frame returns to the pool
  }
  if (player.joinable()) player.join();
  const vlpground::PipelineStats s = pipeline.stats();
  std::printf("%llu frames delivered, %llu dropped\n",
              static_cast<unsigned long long>(s.frames_delivered),
              static_cast<unsigned long long>(s.frames_dropped));
}
