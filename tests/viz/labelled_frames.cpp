#include "labelled_frames.hpp"

#include "test_data.hpp"
#include "vlpground/driver/capture_reader.hpp"

namespace vlpground::test {

std::vector<OwnedLabelledFrame> labelled_frames(const std::string& name) {
  PcapSourceConfig pcap;
  pcap.path = project_pcap(name).string();
  CaptureReader reader(open_pcap_source(pcap));
  GroundDetector detector;
  std::vector<OwnedLabelledFrame> out;
  while (true) {
    OwnedLabelledFrame f{std::make_unique<Frame>(), std::make_unique<GroundResult>(),
                         out.size()};
    if (reader.next(*f.frame) != ReadStatus::frame) break;
    detector.detect(*f.frame, *f.ground);
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace vlpground::test
