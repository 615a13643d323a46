// Builds DecodedPackets directly (no bytes, no decoder) for assembler tests and benchmarks:
// a sensor spinning at a settable rpm, firing on the VLP-16's exact time grid.
#pragma once

#include <cstdint>

#include "vlpground/driver/packet_decoder.hpp"

namespace vlpground::test {

class SyntheticStream {
 public:
  SyntheticStream(double rpm, ReturnMode mode, double start_azimuth_deg = 123.45,
                  std::int64_t start_ns = 1'700'000'000'000'000'000)
      : rpm_(rpm), mode_(mode), azimuth_deg_(start_azimuth_deg), time_ns_(start_ns) {}

  void set_rpm(double rpm) { rpm_ = rpm; }
  [[nodiscard]] int columns_per_packet() const { return mode_ == ReturnMode::dual ? 12 : 24; }

  /// Fills `out` with the next packet and advances the stream by one packet period.
  void next(DecodedPacket& out);
  /// Advances the stream by `packets` packet periods without producing them (loss, FOV).
  void skip(int packets);

  /// Distance of (laser, layer) in the packet's column `global_column` (encodes identity).
  static float distance_of(std::uint64_t global_column, int laser, int layer);

 private:
  [[nodiscard]] double deg_per_ns() const { return rpm_ * 360.0 / 60e9; }
  void advance_column();

  double rpm_;
  ReturnMode mode_;
  double azimuth_deg_;
  std::int64_t time_ns_;
  std::uint64_t packet_index_ = 0;
  std::uint64_t global_column_ = 0;
};

}  // namespace vlpground::test
