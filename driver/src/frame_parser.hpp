// Pure link-layer / IP / UDP parsing of one captured frame (private to the driver).
//
// Finds the UDP datagram inside a frame of any supported link type without copying:
// Ethernet (with any number of 802.1Q / 802.1ad / QinQ tags), Linux cooked SLL and SLL2,
// raw IP, BSD loopback (DLT_NULL / DLT_LOOP, family in either byte order); IPv4 (options via
// IHL) and IPv6 (hop-by-hop, routing, destination-options and AH extension headers skipped).
// Fragments are reported, never reassembled. Thread-safe (no state).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace vlpground::driver_detail {

/// pcap link types (the DLT_* values libpcap's pcap_datalink() reports on Linux, which are
/// also the LINKTYPE_* values for these).
inline constexpr int kLinkNull = 0;
inline constexpr int kLinkEthernet = 1;
inline constexpr int kLinkRawA = 12;   // DLT_RAW on most systems
inline constexpr int kLinkRawB = 14;   // DLT_RAW on OpenBSD
inline constexpr int kLinkRaw = 101;   // LINKTYPE_RAW
inline constexpr int kLinkLoop = 108;  // DLT_LOOP (OpenBSD loopback, network byte order)
inline constexpr int kLinkSll = 113;
inline constexpr int kLinkSll2 = 276;

[[nodiscard]] bool is_supported_link_type(int link_type);

/// An IPv4 or IPv6 address in network byte order (IPv4 uses the first 4 bytes).
struct IpAddress {
  std::uint8_t version = 0;  // 4 or 6; 0 = none
  std::array<std::uint8_t, 16> bytes{};
  [[nodiscard]] bool operator==(const IpAddress&) const = default;
};

/// Parses "192.168.1.201" or "fe80::1"; nullopt when it is neither.
[[nodiscard]] std::optional<IpAddress> parse_ip_address(std::string_view text);

enum class FrameKind : std::uint8_t {
  udp,        // `datagram` is filled
  other,      // not UDP over IP (ARP, TCP, unknown link payload, malformed headers)
  fragment,   // an IPv4 or IPv6 fragment
  truncated,  // the headers claim more bytes than the frame holds
};

struct UdpDatagram {
  IpAddress source;
  std::uint16_t source_port = 0;
  std::uint16_t destination_port = 0;
  std::span<const std::uint8_t> payload;  // per the UDP length field, link padding excluded
};

/// Classifies `frame` (captured bytes of one record of link type `link_type`).
[[nodiscard]] FrameKind parse_frame(int link_type, std::span<const std::uint8_t> frame,
                                    UdpDatagram& out);

}  // namespace vlpground::driver_detail
