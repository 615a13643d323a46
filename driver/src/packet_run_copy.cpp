#include "packet_run_copy.hpp"

#include <array>
#include <cstring>

#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::driver_detail {

namespace {

// Fixed-size copies compile to vector moves; a runtime-sized loop becomes a memmove call,
// which costs more than the copy for 12 or 24 cells.
template <std::size_t N, class T>
void copy_cells(const T* from, T* to, std::size_t n) {
  if constexpr (N > 0) {
    std::memcpy(to, from, N * sizeof(T));
  } else {
    std::memcpy(to, from, n * sizeof(T));
  }
}

struct RunShape {
  std::size_t first_in_packet;
  std::size_t count;
  std::size_t first_col;
};

template <std::size_t N>
void copy_layer_row(const DecodedPacket& packet, const PacketLayer& src, std::size_t laser,
                    const float* base_us, float laser_us, const RunShape& run, std::size_t i0,
                    ReturnLayer& dst) {
  const std::size_t c0 = run.first_in_packet;
  const std::size_t n = N > 0 ? N : run.count;
  const float* range = &src.distance_m[laser][c0];
  copy_cells<N>(range, &dst.range_m[i0], n);
  copy_cells<N>(&src.x_m[laser][c0], &dst.x_m[i0], n);
  copy_cells<N>(&src.y_m[laser][c0], &dst.y_m[i0], n);
  copy_cells<N>(&src.z_m[laser][c0], &dst.z_m[i0], n);
  copy_cells<N>(&src.intensity[laser][c0], &dst.intensity[i0], n);
  copy_cells<N>(&packet.azimuth_deg[laser][c0], &dst.azimuth_deg[i0], n);
  float* __restrict time = &dst.time_offset_us[i0];
  std::uint8_t* __restrict valid = &dst.valid[i0];
  for (std::size_t j = 0; j < n; ++j) {
    time[j] = base_us[j] + laser_us;
    valid[j] = range[j] > 0.f ? 1 : 0;
  }
}

template <std::size_t N>
void copy_run(const DecodedPacket& packet, const RunShape& run, Frame& frame) {
  const std::size_t n = N > 0 ? N : run.count;
  // Firing time of laser 0 of each column relative to the frame start; laser k adds k * 2.304.
  std::array<float, kMaxColumnsPerPacket> base_us;
  for (std::size_t j = 0; j < n; ++j) {
    base_us[j] =
        static_cast<float>(static_cast<double>(packet.column_time_ns[run.first_in_packet + j] -
                                               frame.meta.first_time_ns) *
                           1e-3);
  }
  const int layers = frame.layers();
  for (int ring = 0; ring < kLasers; ++ring) {
    const std::size_t laser = frame.laser_of_ring[ring];
    const std::size_t i0 = frame.index(ring, static_cast<int>(run.first_col));
    const auto laser_us = static_cast<float>(static_cast<double>(laser) * kFiringIntervalNs * 1e-3);
    for (int l = 0; l < layers; ++l) {
      copy_layer_row<N>(packet, packet.layer[static_cast<std::size_t>(l)], laser, base_us.data(),
                        laser_us, run, i0, frame.layer[l]);
    }
    if (layers == 2) {
      copy_cells<N>(&packet.same_echo[laser][run.first_in_packet], &frame.same_echo[i0], n);
    } else {
      std::memset(&frame.same_echo[i0], 0, n);
    }
  }
}

}  // namespace

VLPGROUND_VECTOR_CLONES
void copy_packet_run(const DecodedPacket& packet, int first_in_packet, int count, int first_col,
                     Frame& frame) {
  const RunShape run{static_cast<std::size_t>(first_in_packet), static_cast<std::size_t>(count),
                     static_cast<std::size_t>(first_col)};
  if (first_in_packet == 0 && count == kMaxColumnsPerPacket) {
    copy_run<kMaxColumnsPerPacket>(packet, run, frame);  // a whole single-return packet
  } else if (first_in_packet == 0 && count == kBlocksPerPacket) {
    copy_run<kBlocksPerPacket>(packet, run, frame);  // a whole dual-return packet
  } else {
    copy_run<0>(packet, run, frame);
  }
}

}  // namespace vlpground::driver_detail
