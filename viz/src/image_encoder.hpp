// /vlpground/range_image: the 16 x N range image as a foxglove.RawImage (rgb8), one pixel
// per cell of the strongest (or only) return: top row = highest ring, columns in firing
// order. Ground green, obstacles red, brighter when nearer; no return black.
#pragma once

#include <span>
#include <vector>

#include "foxglove/RawImage.pb.h"
#include "vlpground/pipeline.hpp"
#include "vlpground/viz/channels.hpp"

namespace vlpground::viz::detail {

class ImageEncoder {
 public:
  explicit ImageEncoder(const FrameEncoderConfig& config);
  std::span<const std::byte> encode(const LabelledFrame& frame);
  static const google::protobuf::Descriptor* descriptor() {
    return foxglove::RawImage::descriptor();
  }

 private:
  float max_range_m_;
  foxglove::RawImage message_;
  std::vector<std::byte> buffer_;
};

}  // namespace vlpground::viz::detail
