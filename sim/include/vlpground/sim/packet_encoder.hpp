// Encodes VLP-16 data and position packets byte for byte as the manual describes. Used by the
// simulator and by the driver's round-trip tests (one encoder, independent of the decoder).
//
// Thread-safety: free functions on caller-owned buffers.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "vlpground/driver/position_packet.hpp"
#include "vlpground/types.hpp"

namespace vlpground::sim {

/// Wire-level content of one 1206-byte data packet.
struct DataPacketFields {
  std::array<std::uint16_t, 12> azimuth_centideg{};              // per block, 0..35999
  std::array<std::array<std::uint16_t, 32>, 12> distance_2mm{};  // per block, channel
  std::array<std::array<std::uint8_t, 32>, 12> reflectivity{};
  std::uint32_t stamp_us_past_hour = 0;
  std::uint8_t return_mode = kModeStrongest;
  std::uint8_t product = kProductVlp16;
};

/// Writes exactly 1206 bytes.
void encode_data_packet(const DataPacketFields& fields, std::span<std::uint8_t, 1206> out);

/// Writes exactly 512 bytes: stamp at 198, PPS at 202, `nmea` from 206 (NUL padded, cut to fit).
void encode_position_packet(std::uint32_t stamp_us_past_hour, PpsStatus pps,
                            const std::string& nmea, std::span<std::uint8_t, 512> out);

/// A "$GPRMC,...*hh" sentence (with checksum and CRLF) for the UTC time `utc_ns`.
std::string make_gprmc(std::int64_t utc_ns, bool valid, double latitude_deg, double longitude_deg,
                       double speed_knots, double course_deg);

}  // namespace vlpground::sim
