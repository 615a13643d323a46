// /vlpground/points: every valid return of a labelled frame as a foxglove.PointCloud.
//
// Point layout (16 bytes, little-endian): x y z float32 (m, sensor frame; the message's pose
// places the sensor in the vehicle frame), intensity uint8, ring uint8 (0 = lowest beam),
// label uint8 (1 ground, 2 obstacle), return uint8 (0 strongest/only, 1 last in dual mode).
// Order: column by column, lasers in firing order, then layers -- the order of the CSV.
#pragma once

#include <span>
#include <vector>

#include "foxglove/PointCloud.pb.h"
#include "vlpground/pipeline.hpp"
#include "vlpground/viz/channels.hpp"

namespace vlpground::viz::detail {

inline constexpr std::uint32_t kPointStride = 16;

class PointsEncoder {
 public:
  explicit PointsEncoder(const FrameEncoderConfig& config);
  std::span<const std::byte> encode(const LabelledFrame& frame);
  static const google::protobuf::Descriptor* descriptor() {
    return foxglove::PointCloud::descriptor();
  }

 private:
  foxglove::PointCloud message_;
  std::vector<std::byte> buffer_;
};

}  // namespace vlpground::viz::detail
