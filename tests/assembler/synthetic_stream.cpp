#include "synthetic_stream.hpp"

#include <cmath>

namespace vlpground::test {
namespace {

float wrap(double deg) {
  double w = std::fmod(deg, 360.0);
  if (w < 0) w += 360.0;
  return static_cast<float>(w >= 360.0 ? 0.0 : w);
}

}  // namespace

float SyntheticStream::distance_of(std::uint64_t global_column, int laser, int layer) {
  if (laser == 5 && global_column % 3 == 0) return 0.f;  // some missing returns
  return static_cast<float>(global_column % 97) + 0.5f * static_cast<float>(laser) +
         (layer == 1 ? 100.f : 1.f);
}

void SyntheticStream::advance_column() {
  time_ns_ += kSequencePeriodNs;
  azimuth_deg_ += deg_per_ns() * static_cast<double>(kSequencePeriodNs);
  ++global_column_;
}

void SyntheticStream::next(DecodedPacket& out) {
  out.mode = mode_;
  out.model = Model::vlp16;
  out.column_count = columns_per_packet();
  out.time_ns = time_ns_;
  out.receive_ns = time_ns_ + 1'400'000;
  out.packet_index = packet_index_++;
  out.first_azimuth_centideg = static_cast<std::uint16_t>(wrap(azimuth_deg_) * 100.f) % 36000;
  for (int c = 0; c < out.column_count; ++c) {
    const auto uc = static_cast<std::size_t>(c);
    out.column_time_ns[uc] = time_ns_;
    for (int laser = 0; laser < kLasers; ++laser) {
      const auto l = static_cast<std::size_t>(laser);
      out.azimuth_deg[l][uc] =
          wrap(azimuth_deg_ + deg_per_ns() * static_cast<double>(laser * kFiringIntervalNs));
      for (int layer = 0; layer < 2; ++layer) {
        PacketLayer& dst = out.layer[static_cast<std::size_t>(layer)];
        const float distance = distance_of(global_column_, laser, layer);
        dst.distance_m[l][uc] = distance;
        dst.x_m[l][uc] = distance * 0.5f;
        dst.y_m[l][uc] = static_cast<float>(laser);
        dst.z_m[l][uc] = static_cast<float>(layer);
        dst.intensity[l][uc] = static_cast<std::uint8_t>(laser * 10 + layer);
      }
      out.same_echo[l][uc] = static_cast<std::uint8_t>((l + global_column_) % 2);
    }
    advance_column();
  }
}

void SyntheticStream::skip(int packets) {
  for (int p = 0; p < packets; ++p) {  // lost packets never reach the decoder: no index
    for (int c = 0; c < columns_per_packet(); ++c) advance_column();
  }
}

}  // namespace vlpground::test
