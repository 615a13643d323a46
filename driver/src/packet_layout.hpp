// Byte layout of a VLP-16 family data packet (1206 bytes: 12 blocks of 100 bytes, then the
// stamp, the return-mode byte and the product byte) and the stamp's hour wrap (private to
// the driver).
#pragma once

#include <cstddef>
#include <cstdint>

namespace vlpground::driver_detail {

inline constexpr std::size_t kBlockBytes = 100;
inline constexpr std::size_t kStampOffset = 1200;    // microseconds past the hour, LE u32
inline constexpr std::size_t kModeOffset = 1204;     // return mode
inline constexpr std::size_t kProductOffset = 1205;  // product (model) byte
inline constexpr std::int64_t kHourUs = 3'600'000'000;

/// `later - earlier` in microseconds on the sensor's clock, whose stamps wrap at the hour.
[[nodiscard]] inline std::int64_t stamp_gap_us(std::uint32_t earlier, std::uint32_t later) {
  std::int64_t gap = std::int64_t{later} - std::int64_t{earlier};
  if (gap < 0) gap += kHourUs;
  return gap;
}

}  // namespace vlpground::driver_detail
