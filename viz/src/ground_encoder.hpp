// /vlpground/ground: the fitted terrain as a foxglove.SceneUpdate with one entity "ground":
// per segment (the four quadrants around the partition centre) a patch of its plane over
// its cell (two triangles; green when the segment has ground of its own, amber when its
// plane was inherited from a neighbour, transparent when it has none) and the cell's
// outline on the plane (the partition lines). Entity metadata: frame (FrameMeta::sequence),
// delivered, complete, detect_ms, ground_returns, obstacle_returns.
#pragma once

#include <span>
#include <vector>

#include "foxglove/SceneUpdate.pb.h"
#include "vlpground/pipeline.hpp"
#include "vlpground/viz/channels.hpp"

namespace vlpground::viz::detail {

class GroundEncoder {
 public:
  explicit GroundEncoder(const FrameEncoderConfig& config);
  std::span<const std::byte> encode(const LabelledFrame& frame);
  static const google::protobuf::Descriptor* descriptor() {
    return foxglove::SceneUpdate::descriptor();
  }

 private:
  foxglove::SceneUpdate message_;
  std::vector<std::byte> buffer_;
};

}  // namespace vlpground::viz::detail
