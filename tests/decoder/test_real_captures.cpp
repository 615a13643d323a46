// The decoder on the real captures: product-byte quirks and another sensor family.
#include <catch2/catch.hpp>

#include "classic_pcap.hpp"
#include "test_data.hpp"
#include "vlpground/driver/packet_decoder.hpp"

namespace {

using namespace vlpground;

struct Outcome {
  std::uint64_t ok = 0, not_vlp16 = 0, other = 0;
};

Outcome decode_all(PacketDecoder& decoder, const test::PcapPayloads& payloads) {
  Outcome o;
  DecodedPacket out;
  for (const auto& p : payloads.data) {
    switch (decoder.decode(p.bytes, p.receive_ns, out)) {
      case DecodeStatus::ok:
        ++o.ok;
        break;
      case DecodeStatus::not_vlp16:
        ++o.not_vlp16;
        break;
      default:
        ++o.other;
        break;
    }
  }
  return o;
}

}  // namespace

TEST_CASE("VLP-16 captures whose product byte says 0x21 decode with one warning",
          "[decoder][real]") {
  for (const char* name :
       {"vlp16_county_fair_productbyte21.pcap", "vlp16_1200rpm_productbyte21.pcap"}) {
    const auto path = test::shared_file("real", name);
    VLPGROUND_REQUIRE_SHARED(path);
    INFO(name);
    const auto payloads = test::read_classic_pcap(*path);
    REQUIRE(payloads.data.size() > 50);
    PacketDecoder decoder;
    const Outcome o = decode_all(decoder, payloads);
    CHECK(o.ok == payloads.data.size());
    CHECK(decoder.counters().product_mismatch == payloads.data.size());
    CHECK(decoder.warning_count() == 1);
    CHECK(decoder.last_warning().find("0x21") != std::string::npos);
  }
}

TEST_CASE("HDL-32E captures are recognised as not a VLP-16", "[decoder][real]") {
  for (const char* name : {"hdl32e_short.pcap", "hdl32e_monterey.pcap"}) {
    const auto path = test::shared_file("real", name);
    VLPGROUND_REQUIRE_SHARED(path);
    INFO(name);
    const auto payloads = test::read_classic_pcap(*path);
    REQUIRE(payloads.data.size() > 50);
    PacketDecoder decoder;
    const Outcome o = decode_all(decoder, payloads);
    CHECK(o.ok <= 3);  // a single packet cannot tell; three gaps of 553 us can
    CHECK(o.not_vlp16 == payloads.data.size() - o.ok);
    CHECK(decoder.counters().not_vlp16 == o.not_vlp16);
    CHECK(decoder.last_warning().find("not a VLP-16") != std::string::npos);
  }
}

TEST_CASE("genuine VLP-16 captures decode without warnings", "[decoder][real]") {
  for (const char* name : {"vlp16_dual_close_range.pcap", "vlp16_outdoor_600rpm.pcap",
                           "vlp16_indoor_gps.pcap", "vlp16_short.pcap"}) {
    const auto path = test::shared_file("real", name);
    VLPGROUND_REQUIRE_SHARED(path);
    INFO(name);
    const auto payloads = test::read_classic_pcap(*path);
    PacketDecoder decoder;
    const Outcome o = decode_all(decoder, payloads);
    CHECK(o.ok == payloads.data.size());
    CHECK(decoder.warning_count() == 0);
  }
}
