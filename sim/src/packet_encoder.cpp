// Byte-exact encoder for VLP-16 data and position packets (see docs/vlp16-facts.md).
#include "vlpground/sim/packet_encoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

namespace vlpground::sim {
namespace {

constexpr std::size_t kBlockBytes = 100;
constexpr std::size_t kStampOffset = 1200;
constexpr std::size_t kPositionStampOffset = 198;
constexpr std::size_t kPpsOffset = 202;
constexpr std::size_t kNmeaOffset = 206;

void store_le16(std::uint8_t* dst, std::uint16_t v) {
  const std::uint8_t bytes[2] = {static_cast<std::uint8_t>(v & 0xFFu),
                                 static_cast<std::uint8_t>(v >> 8)};
  std::memcpy(dst, bytes, 2);
}

void store_le32(std::uint8_t* dst, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) dst[i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu);
}

// NMEA ddmm.mmmm (latitude, 2 degree digits) or dddmm.mmmm (longitude, 3 digits).
std::string nmea_angle(double deg, int degree_digits) {
  const double a = std::fabs(deg);
  const int whole = static_cast<int>(a);
  const double minutes = (a - whole) * 60.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%0*d%07.4f", degree_digits, whole, minutes);
  return buf;
}

}  // namespace

void encode_data_packet(const DataPacketFields& fields, std::span<std::uint8_t, 1206> out) {
  std::uint8_t* p = out.data();
  for (std::size_t b = 0; b < 12; ++b) {
    std::uint8_t* block = p + b * kBlockBytes;
    block[0] = 0xFF;
    block[1] = 0xEE;
    store_le16(block + 2, fields.azimuth_centideg[b]);
    for (std::size_t c = 0; c < 32; ++c) {
      store_le16(block + 4 + 3 * c, fields.distance_2mm[b][c]);
      block[4 + 3 * c + 2] = fields.reflectivity[b][c];
    }
  }
  store_le32(p + kStampOffset, fields.stamp_us_past_hour);
  p[1204] = fields.return_mode;
  p[1205] = fields.product;
}

void encode_position_packet(std::uint32_t stamp_us_past_hour, PpsStatus pps,
                            const std::string& nmea, std::span<std::uint8_t, 512> out) {
  std::fill(out.begin(), out.end(), std::uint8_t{0});
  store_le32(out.data() + kPositionStampOffset, stamp_us_past_hour);
  out[kPpsOffset] = static_cast<std::uint8_t>(pps);
  // Keep at least one NUL after the sentence.
  const std::size_t n = std::min(nmea.size(), out.size() - kNmeaOffset - 1);
  std::memcpy(out.data() + kNmeaOffset, nmea.data(), n);
}

std::string make_gprmc(std::int64_t utc_ns, bool valid, double latitude_deg, double longitude_deg,
                       double speed_knots, double course_deg) {
  std::int64_t seconds = utc_ns / 1'000'000'000;
  std::int64_t rem_ns = utc_ns % 1'000'000'000;
  if (rem_ns < 0) {
    rem_ns += 1'000'000'000;
    --seconds;
  }
  const auto t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  const int centis = static_cast<int>(rem_ns / 10'000'000);
  char body[160];
  std::snprintf(body, sizeof body,
                "GPRMC,%02d%02d%02d.%02d,%c,%s,%c,%s,%c,%05.1f,%05.1f,%02d%02d%02d,,,%c",
                tm.tm_hour, tm.tm_min, tm.tm_sec, centis, valid ? 'A' : 'V',
                nmea_angle(latitude_deg, 2).c_str(), latitude_deg < 0 ? 'S' : 'N',
                nmea_angle(longitude_deg, 3).c_str(), longitude_deg < 0 ? 'W' : 'E', speed_knots,
                course_deg, tm.tm_mday, tm.tm_mon + 1, tm.tm_year % 100, valid ? 'A' : 'N');
  std::uint8_t checksum = 0;
  for (const char* c = body; *c != '\0'; ++c) checksum ^= static_cast<std::uint8_t>(*c);
  char full[200];
  std::snprintf(full, sizeof full, "$%s*%02X\r\n", body, checksum);
  return full;
}

}  // namespace vlpground::sim
