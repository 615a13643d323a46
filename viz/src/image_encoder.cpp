#include "image_encoder.hpp"

#include <algorithm>

#include "proto_util.hpp"

namespace vlpground::viz::detail {
namespace {

constexpr int kChannels = 3;

struct Rgb {
  std::uint8_t r, g, b;
};

// Full colour at 0 m, 30 % of it at max_range_m and beyond.
Rgb colour_of(GroundLabel label, float range_m, float max_range_m) {
  const float shade = 1.0f - 0.7f * std::min(range_m / max_range_m, 1.0f);
  const auto c = [shade](float full) { return static_cast<std::uint8_t>(full * shade); };
  switch (label) {
    case GroundLabel::ground:
      return {c(40), c(220), c(70)};
    case GroundLabel::obstacle:
      return {c(235), c(50), c(40)};
    case GroundLabel::no_return:
      break;
  }
  return {c(120), c(120), c(120)};  // a return the detector left unlabelled
}

}  // namespace

ImageEncoder::ImageEncoder(const FrameEncoderConfig& config)
    : max_range_m_(config.image_max_range_m) {
  message_.set_frame_id(config.frame_id);
  message_.set_encoding("rgb8");
  message_.set_height(kLasers);
}

std::span<const std::byte> ImageEncoder::encode(const LabelledFrame& lf) {
  const Frame& frame = lf.frame;
  const GroundResult& ground = lf.ground;
  const ReturnLayer& layer = frame.layer[kStrongestLayer];
  const auto width = static_cast<std::size_t>(frame.columns());
  set_time(*message_.mutable_timestamp(), frame.meta.first_time_ns);
  message_.set_width(static_cast<std::uint32_t>(width));
  message_.set_step(static_cast<std::uint32_t>(width * kChannels));
  std::string& data = *message_.mutable_data();
  data.assign(width * kChannels * kLasers, '\0');

  for (int row = 0; row < kLasers; ++row) {
    const int ring = kLasers - 1 - row;
    char* out = data.data() + static_cast<std::size_t>(row) * width * kChannels;
    const std::size_t ground_row =
        static_cast<std::size_t>(ring) * static_cast<std::size_t>(ground.stride);
    for (std::size_t col = 0; col < width; ++col) {
      const std::size_t cell = frame.index(ring, static_cast<int>(col));
      if (layer.valid[cell] == 0) continue;
      const std::size_t g = ground_row + col;
      const auto label = g < ground.label[0].size() ? static_cast<GroundLabel>(ground.label[0][g])
                                                    : GroundLabel::no_return;
      const Rgb rgb = colour_of(label, layer.range_m[cell], max_range_m_);
      out[col * kChannels + 0] = static_cast<char>(rgb.r);
      out[col * kChannels + 1] = static_cast<char>(rgb.g);
      out[col * kChannels + 2] = static_cast<char>(rgb.b);
    }
  }
  return serialize(message_, buffer_);
}

}  // namespace vlpground::viz::detail
