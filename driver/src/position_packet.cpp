#include "vlpground/driver/position_packet.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

#include "le_load.hpp"

namespace vlpground {
namespace {

constexpr std::size_t kStampOffset = 198;
constexpr std::size_t kPpsOffset = 202;
constexpr std::size_t kNmeaOffset = 206;
constexpr std::size_t kPacketBytes = 512;
constexpr int kFields = 12;  // RMC fields after the talker: time .. mode (mode optional)

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
std::int64_t days_from_civil(int y, int m, int d) {
  y -= m <= 2;
  const int era = (y >= 0 ? y : y - 399) / 400;
  const int yoe = y - era * 400;
  const int doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return std::int64_t{era} * 146097 + doe - 719468;
}

bool parse_double(std::string_view text, double& out) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc{} && end == text.data() + text.size() && std::isfinite(out);
}

bool parse_digits(std::string_view text, int& out) {
  out = 0;
  if (text.empty()) return false;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    out = out * 10 + (c - '0');
  }
  return true;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// "ddmm.mmmm" (2 or 3 degree digits) with hemisphere N/S/E/W; empty -> 0 and true.
bool parse_angle(std::string_view value, std::string_view hemisphere, int degree_digits,
                 double& out) {
  out = 0.0;
  if (value.empty() && hemisphere.empty()) return true;
  if (value.size() < static_cast<std::size_t>(degree_digits) + 2 || hemisphere.size() != 1)
    return false;
  int degrees = 0;
  double minutes = 0.0;
  if (!parse_digits(value.substr(0, static_cast<std::size_t>(degree_digits)), degrees) ||
      !parse_double(value.substr(static_cast<std::size_t>(degree_digits)), minutes) ||
      minutes < 0.0 || minutes >= 60.0) {
    return false;
  }
  out = degrees + minutes / 60.0;
  const char h = hemisphere[0];
  if (h == 'S' || h == 'W') out = -out;
  return h == 'N' || h == 'S' || h == 'E' || h == 'W';
}

bool parse_time(std::string_view t, Gprmc& g) {
  if (t.size() < 6 || !parse_digits(t.substr(0, 2), g.hour) ||
      !parse_digits(t.substr(2, 2), g.minute) || !parse_double(t.substr(4), g.second)) {
    return false;
  }
  return g.hour < 24 && g.minute < 60 && g.second >= 0.0 && g.second < 61.0;
}

bool parse_date(std::string_view d, Gprmc& g) {
  int yy = 0;
  if (d.size() != 6 || !parse_digits(d.substr(0, 2), g.day) ||
      !parse_digits(d.substr(2, 2), g.month) || !parse_digits(d.substr(4, 2), yy)) {
    return false;
  }
  g.year = yy < 80 ? 2000 + yy : 1900 + yy;
  return g.day >= 1 && g.day <= 31 && g.month >= 1 && g.month <= 12;
}

bool parse_optional_number(std::string_view text, double& out) {
  out = 0.0;
  return text.empty() || parse_double(text, out);
}

}  // namespace

std::int64_t Gprmc::utc_ns() const {
  const std::int64_t days = days_from_civil(year, month, day);
  const std::int64_t whole = (days * 24 + hour) * 3600 + std::int64_t{minute} * 60;
  return whole * 1'000'000'000 + std::llround(second * 1e9);
}

Gprmc parse_gprmc(const char* sentence, std::size_t length) {
  Gprmc g;
  if (sentence == nullptr) return g;
  std::string_view s(sentence, length);
  while (!s.empty() && (s.back() == '\r' || s.back() == '\n' || s.back() == '\0'))
    s.remove_suffix(1);
  if (!s.starts_with("$GPRMC,") && !s.starts_with("$GNRMC,")) return g;
  const std::size_t star = s.rfind('*');
  if (star == std::string_view::npos || star + 3 != s.size()) return g;
  unsigned sum = 0;
  for (std::size_t i = 1; i < star; ++i) sum ^= static_cast<unsigned char>(s[i]);
  const int hi = hex_value(s[star + 1]);
  const int lo = hex_value(s[star + 2]);
  g.checksum_ok = hi >= 0 && lo >= 0 && static_cast<unsigned>(hi * 16 + lo) == sum;
  if (!g.checksum_ok) return g;

  std::array<std::string_view, kFields> f{};
  std::string_view body = s.substr(7, star - 7);
  int n = 0;
  for (;;) {
    const std::size_t comma = body.find(',');
    if (n == kFields) return g;  // too many fields
    f[static_cast<std::size_t>(n++)] = body.substr(0, comma);
    if (comma == std::string_view::npos) break;
    body.remove_prefix(comma + 1);
  }
  if (n < 9) return g;  // up to the date at least
  // Fields: 0 time, 1 status, 2 lat, 3 N/S, 4 lon, 5 E/W, 6 speed, 7 course, 8 date, ...
  if (!parse_time(f[0], g) || !parse_date(f[8], g)) return g;
  if (f[1] != "A" && f[1] != "V") return g;
  g.valid = f[1] == "A";
  if (!parse_angle(f[2], f[3], 2, g.latitude_deg) || !parse_angle(f[4], f[5], 3, g.longitude_deg) ||
      std::abs(g.latitude_deg) > 90.0 || std::abs(g.longitude_deg) > 180.0 ||
      !parse_optional_number(f[6], g.speed_knots) || !parse_optional_number(f[7], g.course_deg)) {
    g.valid = false;
    return g;
  }
  g.parsed = true;
  return g;
}

bool parse_position_packet(std::span<const std::uint8_t> bytes, std::int64_t receive_ns,
                           PositionPacket& out) {
  out.receive_ns = receive_ns;
  out.gprmc = Gprmc{};
  out.sentence[0] = '\0';
  if (bytes.size() != kPacketBytes) return false;
  out.stamp_us_past_hour = driver_detail::load_le32(bytes.data() + kStampOffset);
  const std::uint8_t pps = bytes[kPpsOffset];
  out.pps = pps <= 3 ? static_cast<PpsStatus>(pps) : PpsStatus::error;
  const auto* text = reinterpret_cast<const char*>(bytes.data() + kNmeaOffset);
  const std::size_t available = kPacketBytes - kNmeaOffset;
  const auto* nul = static_cast<const char*>(std::memchr(text, '\0', available));
  const std::size_t length = nul != nullptr ? static_cast<std::size_t>(nul - text) : available;
  const std::size_t copied = std::min(length, sizeof out.sentence - 1);
  std::memcpy(out.sentence, text, copied);
  out.sentence[copied] = '\0';
  out.gprmc = parse_gprmc(text, length);
  return true;
}

const char* pps_name(PpsStatus pps) {
  switch (pps) {
    case PpsStatus::absent:
      return "absent";
    case PpsStatus::synchronizing:
      return "synchronizing";
    case PpsStatus::locked:
      return "locked";
    case PpsStatus::error:
      return "error";
  }
  return "absent";
}

}  // namespace vlpground
