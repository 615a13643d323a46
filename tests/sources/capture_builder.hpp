// Test-only construction of frames and capture files, byte by byte, independent of the
// code under test: IPv4/IPv6 UDP, link-layer wrappers, classic pcap and pcapng writers.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace vlpground::test {

using Bytes = std::vector<std::uint8_t>;

/// `size` bytes of a pattern that differs per `seed`, to check delivered payloads.
Bytes pattern_payload(std::size_t size, std::uint8_t seed);

struct Ipv4Spec {
  std::array<std::uint8_t, 4> source{192, 168, 1, 201};
  std::size_t option_bytes = 0;  // multiple of 4, up to 40
  bool more_fragments = false;
  std::uint16_t fragment_offset = 0;  // in 8-byte units
  std::uint8_t protocol = 17;
};
Bytes udp_ipv4(const Bytes& payload, std::uint16_t destination_port, const Ipv4Spec& spec = {});

struct Ipv6Spec {
  std::array<std::uint8_t, 16> source{0x20, 0x01, 0x0d, 0xb8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  /// Extension headers to insert before UDP, by next-header code (0, 43, 60, 51 or 44).
  std::vector<std::uint8_t> extensions;
};
Bytes udp_ipv6(const Bytes& payload, std::uint16_t destination_port, const Ipv6Spec& spec = {});

/// Ethernet II around an IP packet, with the given VLAN tag protocol ids (outermost first).
Bytes ethernet(const Bytes& ip, const std::vector<std::uint16_t>& vlan_tpids = {});
Bytes ethernet_arp();
Bytes linux_sll(const Bytes& ip);
Bytes linux_sll2(const Bytes& ip);
Bytes loopback(const Bytes& ip, std::uint32_t family, bool network_order);

struct Record {
  std::int64_t stamp_ns = 0;
  Bytes bytes;
  std::uint32_t original_length = 0;  // 0 = bytes.size(); larger = snapped record
};

/// Classic pcap (little-endian). `cut_last_bytes` removes bytes from the end of the file to
/// truncate the last record.
void write_pcap(const std::filesystem::path& path, std::uint32_t link_type,
                const std::vector<Record>& records, bool nanosecond = true,
                std::size_t cut_last_bytes = 0);

/// pcapng: SHB, one IDB (if_tsresol = 9, nanoseconds), one EPB per record.
void write_pcapng(const std::filesystem::path& path, std::uint16_t link_type,
                  const std::vector<Record>& records);

}  // namespace vlpground::test
