// The packet encoder writes the manual's byte layout (checked here byte by byte, independently
// of the project's decoder) and well-formed $GPRMC sentences.
#include <array>
#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "vlpground/sim/packet_encoder.hpp"

using namespace vlpground;

namespace {
unsigned le16(const std::uint8_t* p) { return p[0] | (unsigned{p[1]} << 8); }
std::uint32_t le32(const std::uint8_t* p) {
  return p[0] | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}
}  // namespace

TEST_CASE("data packet bytes follow the manual's layout", "[sim][encoder]") {
  sim::DataPacketFields f;
  for (std::size_t b = 0; b < 12; ++b) {
    f.azimuth_centideg[b] = static_cast<std::uint16_t>(35990 + 7 * b) % 36000;
    for (std::size_t c = 0; c < 32; ++c) {
      f.distance_2mm[b][c] = static_cast<std::uint16_t>(1000 * b + 31 * c + 258);
      f.reflectivity[b][c] = static_cast<std::uint8_t>(b * 32 + c);
    }
  }
  f.stamp_us_past_hour = 3'599'999'123u;
  f.return_mode = kModeDual;
  f.product = kProductHiRes;
  std::array<std::uint8_t, 1206> out{};
  sim::encode_data_packet(f, out);
  for (std::size_t b = 0; b < 12; ++b) {
    const std::uint8_t* block = out.data() + 100 * b;
    CHECK(block[0] == 0xFF);
    CHECK(block[1] == 0xEE);
    CHECK(le16(block + 2) == f.azimuth_centideg[b]);
    for (std::size_t c = 0; c < 32; ++c) {
      CHECK(le16(block + 4 + 3 * c) == f.distance_2mm[b][c]);
      CHECK(block[6 + 3 * c] == f.reflectivity[b][c]);
    }
  }
  CHECK(le32(out.data() + 1200) == f.stamp_us_past_hour);
  CHECK(out[1204] == kModeDual);
  CHECK(out[1205] == kProductHiRes);
}

TEST_CASE("GPRMC sentence has the time, date, position and a correct checksum", "[sim][encoder]") {
  // 2023-11-14 22:00:01.25 UTC
  const std::int64_t utc_ns = 1'699'999'201'250'000'000;
  const std::string s = sim::make_gprmc(utc_ns, true, 48.1173, -11.5167, 10.5, 84.4);
  REQUIRE(s.rfind("$GPRMC,220001.25,A,4807.0380,N,01131.0020,W,010.5,084.4,141123,", 0) == 0);
  REQUIRE(s.size() > 5);
  CHECK(s.substr(s.size() - 2) == "\r\n");
  const auto star = s.find('*');
  REQUIRE(star != std::string::npos);
  unsigned sum = 0;
  for (std::size_t i = 1; i < star; ++i) sum ^= static_cast<unsigned char>(s[i]);
  CHECK(std::stoul(s.substr(star + 1, 2), nullptr, 16) == sum);
  CHECK(sim::make_gprmc(utc_ns, false, 0, 0, 0, 0).find(",V,") != std::string::npos);
}

TEST_CASE("position packet places stamp, PPS and sentence", "[sim][encoder]") {
  std::array<std::uint8_t, 512> out;
  out.fill(0xAB);
  const std::string nmea = "$GPRMC,220001,A*00\r\n";
  sim::encode_position_packet(1'017'252u, PpsStatus::locked, nmea, out);
  CHECK(le32(out.data() + 198) == 1'017'252u);
  CHECK(out[202] == 2);
  CHECK(std::string(reinterpret_cast<const char*>(out.data() + 206)) == nmea);
  CHECK(out[0] == 0);
  CHECK(out[511] == 0);
  const std::string too_long(400, 'x');
  sim::encode_position_packet(0, PpsStatus::absent, too_long, out);
  CHECK(out[511] == 0);
  CHECK(out[510] == 'x');
}
