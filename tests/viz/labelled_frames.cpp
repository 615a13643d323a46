#include "labelled_frames.hpp"

#include "test_data.hpp"
#include "vlpground/driver/capture_reader.hpp"

namespace vlpground::test {

std::vector<std::unique_ptr<LabelledFrame>> labelled_frames(const std::string& name) {
  PcapSourceConfig pcap;
  pcap.path = project_pcap(name).string();
  CaptureReader reader(open_pcap_source(pcap));
  GroundDetector detector;
  std::vector<std::unique_ptr<LabelledFrame>> out;
  while (true) {
    auto f = std::make_unique<LabelledFrame>();
    if (reader.next(f->frame) != ReadStatus::frame) break;
    detector.detect(f->frame, f->ground);
    f->timings = {1.5, 2.5};
    f->delivered_index = out.size();
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace vlpground::test
