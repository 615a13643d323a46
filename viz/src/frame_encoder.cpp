#include <cmath>
#include <stdexcept>

#include "ground_encoder.hpp"
#include "image_encoder.hpp"
#include "points_encoder.hpp"
#include "proto_util.hpp"
#include "status_encoder.hpp"
#include "vlpground/viz/channels.hpp"

namespace vlpground::viz {

void FrameEncoderConfig::validate() const {
  if (topic_prefix.empty() || topic_prefix.front() != '/' || topic_prefix.back() == '/') {
    throw std::invalid_argument("foxglove topic_prefix must start with '/' and not end with it: '" +
                                topic_prefix + "'");
  }
  if (frame_id.empty()) throw std::invalid_argument("foxglove frame_id must not be empty");
  if (!(image_max_range_m > 0.0f) || !std::isfinite(image_max_range_m)) {
    throw std::invalid_argument("foxglove image_max_range_m must be > 0");
  }
}

namespace {

ChannelSpec protobuf_channel(std::string topic, const google::protobuf::Descriptor* d) {
  return {std::move(topic), "protobuf", d->full_name(), "protobuf",
          detail::file_descriptor_set(d)};
}

std::vector<ChannelSpec> make_channels(const FrameEncoderConfig& c) {
  std::vector<ChannelSpec> out(kChannelCount);
  out[kPointsChannel] =
      protobuf_channel(c.topic_prefix + "/points", detail::PointsEncoder::descriptor());
  out[kGroundChannel] =
      protobuf_channel(c.topic_prefix + "/ground", detail::GroundEncoder::descriptor());
  out[kRangeImageChannel] =
      protobuf_channel(c.topic_prefix + "/range_image", detail::ImageEncoder::descriptor());
  out[kStatusChannel] = {c.topic_prefix + "/status", "json", "vlpground.Status", "jsonschema",
                         detail::kStatusJsonSchema};
  return out;
}

}  // namespace

struct FrameEncoder::Impl {
  explicit Impl(FrameEncoderConfig c)
      : config((c.validate(), std::move(c))),
        channels(make_channels(config)),
        points(config),
        ground(config),
        image(config) {}

  FrameEncoderConfig config;
  std::vector<ChannelSpec> channels;
  detail::PointsEncoder points;
  detail::GroundEncoder ground;
  detail::ImageEncoder image;
  detail::StatusEncoder status;
};

FrameEncoder::FrameEncoder(FrameEncoderConfig config)
    : impl_(std::make_unique<Impl>(std::move(config))) {}
FrameEncoder::~FrameEncoder() = default;
FrameEncoder::FrameEncoder(FrameEncoder&&) noexcept = default;
FrameEncoder& FrameEncoder::operator=(FrameEncoder&&) noexcept = default;

const std::vector<ChannelSpec>& FrameEncoder::channels() const { return impl_->channels; }
const FrameEncoderConfig& FrameEncoder::config() const { return impl_->config; }

void FrameEncoder::encode(const LabelledFrame& frame, const MessageSink& sink,
                          ChannelMask wanted) {
  const std::int64_t t = frame.frame.meta.first_time_ns;
  const auto want = [wanted](Channel c) { return (wanted >> c & 1u) != 0; };
  if (want(kPointsChannel)) sink(kPointsChannel, t, impl_->points.encode(frame));
  if (want(kGroundChannel)) sink(kGroundChannel, t, impl_->ground.encode(frame));
  if (want(kRangeImageChannel)) sink(kRangeImageChannel, t, impl_->image.encode(frame));
}

void FrameEncoder::encode_status(const PipelineStats& stats, std::int64_t log_time_ns,
                                 const MessageSink& sink) {
  sink(kStatusChannel, log_time_ns, impl_->status.encode(stats));
}

void FrameEncoder::note_position(const PositionPacket& packet) {
  impl_->status.note_position(packet);
}

}  // namespace vlpground::viz
