#include "encoded_stream.hpp"

#include <cmath>

#include "vlpground/sim/packet_encoder.hpp"

namespace vlpground::test {

std::vector<PacketBytes> encode_stream(int count, double rpm, ReturnMode mode,
                                       std::uint32_t start_us_past_hour) {
  const bool dual = mode == ReturnMode::dual;
  const std::int64_t period_ns = dual ? kDualPacketPeriodNs : kSinglePacketPeriodNs;
  const double deg_per_ns = rpm * 360.0 / 60e9;
  std::vector<PacketBytes> out(static_cast<std::size_t>(count));
  sim::DataPacketFields f;
  f.return_mode = dual ? kModeDual : (mode == ReturnMode::last ? kModeLast : kModeStrongest);
  for (int p = 0; p < count; ++p) {
    const std::int64_t t0 = std::int64_t{start_us_past_hour} * 1000 + p * period_ns;
    f.stamp_us_past_hour = static_cast<std::uint32_t>(t0 / 1000);
    for (int b = 0; b < 12; ++b) {
      const int sequence = dual ? (b - b % 2) : 2 * b;  // first sequence of the block
      const double az = std::fmod(
          deg_per_ns * static_cast<double>(t0 + sequence * kSequencePeriodNs) + 17.0, 360.0);
      const auto bi = static_cast<std::size_t>(b);
      f.azimuth_centideg[bi] = static_cast<std::uint16_t>(static_cast<int>(az * 100.0) % 36000);
      for (std::size_t ch = 0; ch < 32; ++ch) {
        f.distance_2mm[bi][ch] =
            static_cast<std::uint16_t>(1000 + 37 * ch + 11 * bi + static_cast<std::size_t>(p % 50));
        f.reflectivity[bi][ch] = static_cast<std::uint8_t>(ch * 7 + bi);
      }
    }
    sim::encode_data_packet(f, out[static_cast<std::size_t>(p)]);
  }
  return out;
}

}  // namespace vlpground::test
