// The pure frame parser on hand-built frames: edge cases a capture file cannot easily show.
#include <catch2/catch.hpp>

#include "capture_builder.hpp"
#include "frame_parser.hpp"

using namespace vlpground::driver_detail;
using vlpground::test::Bytes;

namespace {
FrameKind parse(int link, const Bytes& frame, UdpDatagram& out) {
  return parse_frame(link, std::span<const std::uint8_t>(frame.data(), frame.size()), out);
}
}  // namespace

TEST_CASE("frame parser: finds the UDP payload behind IPv4 options and ignores padding") {
  vlpground::test::Ipv4Spec spec;
  spec.option_bytes = 40;  // IHL 15, the maximum
  const Bytes payload = vlpground::test::pattern_payload(18, 5);
  Bytes frame = vlpground::test::ethernet(vlpground::test::udp_ipv4(payload, 2368, spec));
  frame.resize(frame.size() + 6, 0xEE);  // trailing link padding
  UdpDatagram d;
  REQUIRE(parse(kLinkEthernet, frame, d) == FrameKind::udp);
  CHECK(d.destination_port == 2368);
  CHECK(d.source_port == 51000);
  CHECK(d.source.version == 4);
  CHECK(d.source.bytes[3] == 201);
  CHECK(Bytes(d.payload.begin(), d.payload.end()) == payload);
}

TEST_CASE("frame parser: headers claiming more than the frame holds are truncated") {
  const Bytes ip = vlpground::test::udp_ipv4(vlpground::test::pattern_payload(100, 1), 2368);
  UdpDatagram d;
  for (std::size_t cut : {1u, 50u, 100u, 110u, 127u}) {
    INFO("cut " << cut);
    const Bytes shorter(ip.begin(), ip.end() - static_cast<std::ptrdiff_t>(cut));
    CHECK(parse(kLinkRaw, shorter, d) == FrameKind::truncated);
  }
  CHECK(parse(kLinkEthernet, Bytes(10, 0), d) == FrameKind::truncated);
  CHECK(parse(kLinkSll2, Bytes(19, 0), d) == FrameKind::truncated);
  CHECK(parse(kLinkNull, Bytes(3, 0), d) == FrameKind::truncated);
}

TEST_CASE("frame parser: malformed and foreign frames are 'other'") {
  UdpDatagram d;
  Bytes ip = vlpground::test::udp_ipv4(vlpground::test::pattern_payload(20, 1), 2368);
  Bytes bad_ihl = ip;
  bad_ihl[0] = 0x44;  // IHL 4 < 5
  CHECK(parse(kLinkRaw, bad_ihl, d) == FrameKind::other);
  Bytes bad_udp_length = ip;
  bad_udp_length[20 + 4] = 0;
  bad_udp_length[20 + 5] = 4;  // UDP length < 8
  CHECK(parse(kLinkRaw, bad_udp_length, d) == FrameKind::other);
  Bytes version5 = ip;
  version5[0] = 0x55;
  CHECK(parse(kLinkRaw, version5, d) == FrameKind::other);
  CHECK(parse(kLinkNull, vlpground::test::loopback(ip, 7, false), d) == FrameKind::other);
  CHECK(parse(147, ip, d) == FrameKind::other);  // unsupported link type
  CHECK_FALSE(is_supported_link_type(147));
  CHECK(is_supported_link_type(kLinkSll2));
}

TEST_CASE("frame parser: IPv6 extension header chain is walked to UDP") {
  vlpground::test::Ipv6Spec spec;
  spec.extensions = {0, 60, 43, 60};
  const Bytes payload = vlpground::test::pattern_payload(33, 9);
  UdpDatagram d;
  const Bytes ip = vlpground::test::udp_ipv6(payload, 8308, spec);  // outlives d.payload
  REQUIRE(parse(kLinkRaw, ip, d) == FrameKind::udp);
  CHECK(d.source.version == 6);
  CHECK(d.source.bytes[0] == 0x20);
  CHECK(d.destination_port == 8308);
  CHECK(Bytes(d.payload.begin(), d.payload.end()) == payload);
}

TEST_CASE("frame parser: address text parsing") {
  const auto v4 = parse_ip_address("10.0.0.7");
  REQUIRE(v4);
  CHECK(v4->version == 4);
  CHECK(v4->bytes[0] == 10);
  CHECK(v4->bytes[3] == 7);
  const auto v6 = parse_ip_address("::1");
  REQUIRE(v6);
  CHECK(v6->version == 6);
  CHECK(v6->bytes[15] == 1);
  CHECK_FALSE(parse_ip_address(""));
  CHECK_FALSE(parse_ip_address("10.0.0"));
  CHECK_FALSE(parse_ip_address("velodyne"));
}

TEST_CASE("frame parser: tolerates the VLP-16 position packets' wrong IPv4 total length") {
  const Bytes payload = vlpground::test::pattern_payload(512, 3);
  Bytes ip = vlpground::test::udp_ipv4(payload, 8308);
  ip[2] = 0x04;  // total length 1234 as the sensor writes it, although 540 bytes follow
  ip[3] = 0xD2;
  UdpDatagram d;
  REQUIRE(parse(kLinkRaw, ip, d) == FrameKind::udp);
  CHECK(Bytes(d.payload.begin(), d.payload.end()) == payload);
  ip.pop_back();  // now the UDP length (520) is beyond the frame: truncated after all
  CHECK(parse(kLinkRaw, ip, d) == FrameKind::truncated);
}
