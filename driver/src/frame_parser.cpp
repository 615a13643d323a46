#include "frame_parser.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace vlpground::driver_detail {
namespace {

using Bytes = std::span<const std::uint8_t>;

constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint16_t kEtherIpv6 = 0x86DD;
constexpr std::uint16_t kEtherVlan = 0x8100;
constexpr std::uint16_t kEtherQinQ = 0x88A8;
constexpr std::uint16_t kEtherQinQOld = 0x9100;
constexpr std::uint8_t kProtoUdp = 17;

std::uint16_t load_be16(Bytes b, std::size_t at) {
  return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}

std::uint32_t load_le32(Bytes b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;  // the project targets little-endian hosts (see vlp16-facts.md)
}

FrameKind parse_udp(Bytes ip_payload, const IpAddress& source, UdpDatagram& out) {
  if (ip_payload.size() < 8) return FrameKind::truncated;
  const std::uint16_t udp_length = load_be16(ip_payload, 4);
  if (udp_length < 8) return FrameKind::other;
  if (udp_length > ip_payload.size()) return FrameKind::truncated;
  out.source = source;
  out.source_port = load_be16(ip_payload, 0);
  out.destination_port = load_be16(ip_payload, 2);
  out.payload = ip_payload.subspan(8, udp_length - 8u);
  return FrameKind::udp;
}

FrameKind parse_ipv4(Bytes ip, UdpDatagram& out) {
  if (ip.size() < 20) return FrameKind::truncated;
  const std::size_t header_bytes = (ip[0] & 0x0Fu) * 4u;
  std::size_t total_bytes = load_be16(ip, 2);
  if (header_bytes < 20 || total_bytes < header_bytes) return FrameKind::other;
  if (header_bytes > ip.size()) return FrameKind::truncated;
  // VLP-16 position packets carry a wrong IPv4 total length (1234, the data packets' value),
  // so a length beyond the frame is clamped; the UDP length check still catches truncation.
  total_bytes = std::min(total_bytes, ip.size());
  const std::uint16_t flags_offset = load_be16(ip, 6);
  const bool more_fragments = (flags_offset & 0x2000u) != 0;
  const bool nonzero_offset = (flags_offset & 0x1FFFu) != 0;
  if (more_fragments || nonzero_offset) return FrameKind::fragment;
  if (ip[9] != kProtoUdp) return FrameKind::other;
  IpAddress source;
  source.version = 4;
  std::memcpy(source.bytes.data(), ip.data() + 12, 4);
  return parse_udp(ip.subspan(header_bytes, total_bytes - header_bytes), source, out);
}

FrameKind parse_ipv6(Bytes ip, UdpDatagram& out) {
  if (ip.size() < 40) return FrameKind::truncated;
  const std::size_t payload_bytes = load_be16(ip, 4);
  if (payload_bytes == 0) return FrameKind::other;  // jumbogram: never a Velodyne packet
  if (40 + payload_bytes > ip.size()) return FrameKind::truncated;
  IpAddress source;
  source.version = 6;
  std::memcpy(source.bytes.data(), ip.data() + 8, 16);

  Bytes rest = ip.subspan(40, payload_bytes);
  std::uint8_t next_header = ip[6];
  for (;;) {
    switch (next_header) {
      case kProtoUdp:
        return parse_udp(rest, source, out);
      case 44:  // fragment header
        return FrameKind::fragment;
      case 0:     // hop-by-hop options
      case 43:    // routing
      case 60:    // destination options
      case 51: {  // authentication header: length in 4-byte units minus 2
        if (rest.size() < 8) return FrameKind::truncated;
        const std::size_t length = next_header == 51 ? (rest[1] + 2u) * 4u : (rest[1] + 1u) * 8u;
        if (length > rest.size()) return FrameKind::truncated;
        next_header = rest[0];
        rest = rest.subspan(length);
        break;
      }
      default:
        return FrameKind::other;  // TCP, ICMPv6, ESP, no-next-header, ...
    }
  }
}

FrameKind parse_ip(Bytes ip, UdpDatagram& out) {
  if (ip.empty()) return FrameKind::truncated;
  switch (ip[0] >> 4) {
    case 4:
      return parse_ipv4(ip, out);
    case 6:
      return parse_ipv6(ip, out);
    default:
      return FrameKind::other;
  }
}

// `type` is an EtherType; `rest` the bytes after it. 802.1Q / 802.1ad tags (TCI + the next
// EtherType) may be stacked any number of times.
FrameKind parse_ethertype(std::uint16_t type, Bytes rest, UdpDatagram& out) {
  while (type == kEtherVlan || type == kEtherQinQ || type == kEtherQinQOld) {
    if (rest.size() < 4) return FrameKind::truncated;
    type = load_be16(rest, 2);
    rest = rest.subspan(4);
  }
  if (type == kEtherIpv4 || type == kEtherIpv6) return parse_ip(rest, out);
  return FrameKind::other;  // ARP, LLDP, 802.3 length field, ...
}

// Ethernet (type at 12) and SLL (type at 14): the payload follows the type.
FrameKind parse_type_then_payload(Bytes frame, std::size_t type_at, UdpDatagram& out) {
  if (frame.size() < type_at + 2) return FrameKind::truncated;
  return parse_ethertype(load_be16(frame, type_at), frame.subspan(type_at + 2), out);
}

// BSD loopback: a 4-byte address family in the writer's byte order (DLT_NULL) or network
// order (DLT_LOOP); AF_INET6 differs between BSDs, so the IP version nibble decides.
FrameKind parse_loopback(Bytes frame, UdpDatagram& out) {
  if (frame.size() < 4) return FrameKind::truncated;
  std::uint32_t family = load_le32(frame, 0);
  if (family > 0xFFFFu) family = ntohl(family);
  const bool ipv4 = family == 2;
  const bool ipv6 = family == 10 || family == 24 || family == 28 || family == 30;
  if (!ipv4 && !ipv6) return FrameKind::other;
  return parse_ip(frame.subspan(4), out);
}

}  // namespace

bool is_supported_link_type(int link_type) {
  switch (link_type) {
    case kLinkNull:
    case kLinkEthernet:
    case kLinkRawA:
    case kLinkRawB:
    case kLinkRaw:
    case kLinkLoop:
    case kLinkSll:
    case kLinkSll2:
      return true;
    default:
      return false;
  }
}

std::optional<IpAddress> parse_ip_address(std::string_view text) {
  const std::string zero_terminated(text);
  IpAddress address;
  if (inet_pton(AF_INET, zero_terminated.c_str(), address.bytes.data()) == 1) {
    address.version = 4;
    return address;
  }
  if (inet_pton(AF_INET6, zero_terminated.c_str(), address.bytes.data()) == 1) {
    address.version = 6;
    return address;
  }
  return std::nullopt;
}

FrameKind parse_frame(int link_type, std::span<const std::uint8_t> frame, UdpDatagram& out) {
  switch (link_type) {
    case kLinkEthernet:
      return parse_type_then_payload(frame, 12, out);
    case kLinkSll:  // 16-byte header, protocol type last
      return parse_type_then_payload(frame, 14, out);
    case kLinkSll2:  // 20-byte header, protocol type first
      if (frame.size() < 20) return FrameKind::truncated;
      return parse_ethertype(load_be16(frame, 0), frame.subspan(20), out);
    case kLinkRawA:
    case kLinkRawB:
    case kLinkRaw:
      return parse_ip(frame, out);
    case kLinkNull:
    case kLinkLoop:
      return parse_loopback(frame, out);
    default:
      return FrameKind::other;
  }
}

}  // namespace vlpground::driver_detail
