// The decoder's hot loop: the records of one validated data packet to x/y/z, range,
// azimuth and intensity per laser and column (private to the driver).
//
// Layout: the loop runs laser by laser over the packet's columns, so every output row
// (DecodedPacket::LaserRows) is written contiguously and the arithmetic vectorises. The
// azimuth of laser k in a column is base + k * step (the manual's interpolation is linear
// in the firing time), so its cosine and sine advance by one complex multiplication per
// laser instead of a trigonometric evaluation per return.
//
// Thread-safety: pure functions of their arguments.
#pragma once

#include <array>
#include <cstdint>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/sensor_model.hpp"

namespace vlpground::driver_detail {

/// Per-laser constants of the decode loop, in float, precomputed from a SensorModel.
struct DecodeConstants {
  std::array<float, kLasers> cos_elevation{}, sin_elevation{};
  std::array<float, kLasers> vertical_offset_m{}, distance_correction_m{};
  std::array<float, kLasers> cos_rotation{}, sin_rotation{};  // rot_correction
  float resolution_m = 0.002f;

  static DecodeConstants from(const SensorModel& model);
};

/// Azimuth of the block at `block` in centidegrees, [0, 36000). Real sensors now and then
/// send 36000 (seen in VLP-16 and HDL-32E captures): that is 0 degrees, not malformed.
int block_azimuth(const std::uint8_t* block);

/// Fills the columns, azimuths and returns of `out` from packet bytes `p` (1206 bytes,
/// already validated: flags, azimuths, mode). `time0_ns` is the first firing's time.
void decode_columns(const std::uint8_t* p, const DecodeConstants& constants, bool dual,
                    std::int64_t time0_ns, DecodedPacket& out);

}  // namespace vlpground::driver_detail
