// Basic vocabulary shared by every vlpground library. Header-only, no dependencies.
#pragma once

#include <cstdint>
#include <string_view>

namespace vlpground {

/// Number of lasers (and range-image rows) of the VLP-16 family.
inline constexpr int kLasers = 16;

/// Sensor models of the VLP-16 family. Puck LITE decodes as `vlp16`.
enum class Model : std::uint8_t { vlp16, hires };

/// Where a frame's times come from (FrameMeta::time_source), for fusion stacks.
enum class TimeSource : std::uint8_t {
  host_clock,  // no GPS: the sensor's clock placed on the host clock (hour, offset)
  gps_no_pps,  // a GPS fix arrives but PPS is not locked: the sensor clock is not
               // disciplined; placed on the host clock as without GPS
  gps_pps,     // GPS with PPS locked: UTC (the hour from $GPRMC, the us from the sensor)
};

/// Return mode announced by byte 1204 of a data packet.
enum class ReturnMode : std::uint8_t { strongest, last, dual };

/// Product byte values (byte 1205).
inline constexpr std::uint8_t kProductVlp16 = 0x22;
inline constexpr std::uint8_t kProductHiRes = 0x24;

/// Return-mode byte values (byte 1204).
inline constexpr std::uint8_t kModeStrongest = 0x37;
inline constexpr std::uint8_t kModeLast = 0x38;
inline constexpr std::uint8_t kModeDual = 0x39;

/// Firing timing of the VLP-16 family, in nanoseconds (exact integers).
inline constexpr std::int64_t kFiringIntervalNs = 2304;   // laser k fires 2.304 us after k-1
inline constexpr std::int64_t kSequencePeriodNs = 55296;  // 16 firings + recharge
inline constexpr std::int64_t kSinglePacketPeriodNs = 24 * kSequencePeriodNs;  // 1327.104 us
inline constexpr std::int64_t kDualPacketPeriodNs = 12 * kSequencePeriodNs;    // 663.552 us

/// Layer index of a return in dual mode; single-return frames use only layer 0.
inline constexpr int kStrongestLayer = 0;  // strongest (or the only) return
inline constexpr int kLastLayer = 1;       // last return (dual mode only)

constexpr std::string_view to_string(Model m) { return m == Model::hires ? "hires" : "vlp16"; }

constexpr std::string_view to_string(TimeSource s) {
  switch (s) {
    case TimeSource::host_clock:
      return "host_clock";
    case TimeSource::gps_no_pps:
      return "gps_no_pps";
    case TimeSource::gps_pps:
      return "gps_pps";
  }
  return "?";
}

constexpr std::string_view to_string(ReturnMode m) {
  switch (m) {
    case ReturnMode::strongest:
      return "strongest";
    case ReturnMode::last:
      return "last";
    case ReturnMode::dual:
      return "dual";
  }
  return "?";
}

}  // namespace vlpground
