#include "udp_sender.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "vlpground/driver/packet_source.hpp"

namespace vlpground::test {

void send_capture(const std::string& pcap, std::uint16_t data_port, std::uint16_t position_port,
                  double rate) {
  PcapSourceConfig c;
  c.path = pcap;
  c.rate = rate;
  auto source = open_pcap_source(c);
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  PacketView v;
  while (source->next(v, 5000) == SourceStatus::packet) {
    const std::uint16_t port = v.kind == PacketKind::data ? data_port : position_port;
    if (port == 0) continue;
    to.sin_port = htons(port);
    sendto(fd, v.bytes.data(), v.bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  }
  close(fd);
}

}  // namespace vlpground::test
