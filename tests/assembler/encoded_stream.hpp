// Synthetic 1206-byte data packets (through the project's encoder) for allocation tests and
// benchmarks: a VLP-16 spinning at `rpm` in `mode`, stamps on the exact firing grid.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vlpground/types.hpp"

namespace vlpground::test {

using PacketBytes = std::array<std::uint8_t, 1206>;

/// `count` consecutive data packets starting `start_us_past_hour` into the hour.
std::vector<PacketBytes> encode_stream(int count, double rpm, ReturnMode mode,
                                       std::uint32_t start_us_past_hour = 1'000'000);

}  // namespace vlpground::test
