// Little-endian loads from byte buffers via std::memcpy (private to the driver).
// The caller checks the length first. Thread-safe (pure functions).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace vlpground::driver_detail {

inline std::uint16_t load_le16(const std::uint8_t* p) {
  std::uint16_t v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::big)
    v = static_cast<std::uint16_t>((v >> 8) | (v << 8));
  return v;
}

inline std::uint32_t load_le32(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::big) {
    v = ((v & 0xFFu) << 24) | ((v & 0xFF00u) << 8) | ((v >> 8) & 0xFF00u) | (v >> 24);
  }
  return v;
}

}  // namespace vlpground::driver_detail
