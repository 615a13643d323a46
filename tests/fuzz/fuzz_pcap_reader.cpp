// libFuzzer: arbitrary bytes as a capture file, drained through open_pcap_source and the
// decoder. The input is written to /dev/shm (a RAM file system) because libpcap reads files.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/driver/position_packet.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace vlpground;
  static const std::string path = "/dev/shm/vlpground-fuzz-" + std::to_string(getpid()) + ".pcap";
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
  PcapSourceConfig config;
  config.path = path;
  std::unique_ptr<PacketSource> source;
  try {
    source = open_pcap_source(config);
  } catch (const std::exception&) {
    return 0;  // not a capture: the expected outcome for most inputs
  }
  PacketDecoder decoder;
  DecodedPacket out;
  PositionPacket position;
  PacketView view;
  for (int i = 0; i < 100'000 && source->next(view, 0) == SourceStatus::packet; ++i) {
    if (view.kind == PacketKind::data) {
      decoder.decode(view.bytes, view.receive_ns, out);
    } else {
      parse_position_packet(view.bytes, view.receive_ns, position);
    }
  }
  return 0;
}
