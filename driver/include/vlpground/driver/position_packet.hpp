// 512-byte position packets (UDP 8308): timestamp, PPS status and the $GPRMC sentence.
//
// Thread-safety: free functions on caller-owned values; no shared state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace vlpground {

enum class PpsStatus : std::uint8_t { absent = 0, synchronizing = 1, locked = 2, error = 3 };

/// Parsed $GPRMC sentence. Fields are meaningful only when `parsed` is true.
struct Gprmc {
  bool parsed = false;  // sentence present, well formed, checksum correct
  bool checksum_ok = false;
  bool valid = false;  // status 'A'
  int hour = 0, minute = 0;
  double second = 0.0;
  int day = 0, month = 0, year = 0;  // full year (e.g. 2023)
  double latitude_deg = 0.0;         // + north
  double longitude_deg = 0.0;        // + east
  double speed_knots = 0.0;
  double course_deg = 0.0;
  /// UTC time of the fix as ns since the Unix epoch (only when parsed).
  [[nodiscard]] std::int64_t utc_ns() const;
};

/// Everything a position packet tells. `sentence` is a copy (NUL padded, not allocated).
struct PositionPacket {
  std::uint32_t stamp_us_past_hour = 0;
  PpsStatus pps = PpsStatus::absent;
  Gprmc gprmc;
  char sentence[128] = {};  // the raw NMEA text, NUL terminated
  std::int64_t receive_ns = 0;
};

/// Parses a 512-byte position packet. Returns false (and leaves `out` partly filled) when
/// the size is wrong; a bad or missing sentence is `gprmc.parsed == false`, not an error.
bool parse_position_packet(std::span<const std::uint8_t> bytes, std::int64_t receive_ns,
                           PositionPacket& out);

/// Parses one "$GPRMC,...*hh" sentence (also accepts $GNRMC). Never throws.
Gprmc parse_gprmc(const char* sentence, std::size_t length);

/// "absent", "synchronizing", "locked" or "error": the one spelling every output uses.
const char* pps_name(PpsStatus pps);

}  // namespace vlpground
