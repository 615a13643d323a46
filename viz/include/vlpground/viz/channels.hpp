// Foxglove channels of a labelled frame, encoded once and shared by every viz front-end
// (the WebSocket server, the MCAP recorder, embedding programs).
//
// Channels (docs/foxglove.md states the exact schemas):
//   0 /vlpground/points       foxglove.PointCloud (protobuf): x y z intensity ring label return
//   1 /vlpground/ground       foxglove.SceneUpdate (protobuf): segment planes + partition
//   2 /vlpground/range_image  foxglove.RawImage (protobuf): 16 x N, rgb8, coloured by label
//   3 /vlpground/status       JSON: counters, rates, detect time, latency, GPS/PPS state
//
// Thread-safety: encode() and encode_status() share nothing, so each may run on its own
// thread (one call at a time each); note_position() may be called from any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/position_packet.hpp"
#include "vlpground/pipeline.hpp"

namespace vlpground::viz {

/// One channel as Foxglove WebSocket and MCAP describe it.
struct ChannelSpec {
  std::string topic;             // e.g. "/vlpground/points"
  std::string message_encoding;  // "protobuf" | "json"
  std::string schema_name;       // e.g. "foxglove.PointCloud"
  std::string schema_encoding;   // "protobuf" | "jsonschema"
  std::string schema;            // bytes: a FileDescriptorSet, or JSON Schema text
};

/// Channel indices of FrameEncoder::channels().
enum Channel : std::size_t {
  kPointsChannel = 0,
  kGroundChannel = 1,
  kRangeImageChannel = 2,
  kStatusChannel = 3,
  kChannelCount = 4,
};
/// Bit i set: encode channel i.
using ChannelMask = std::uint32_t;
inline constexpr ChannelMask kAllChannels = (1u << kChannelCount) - 1;

struct FrameEncoderConfig {
  std::string topic_prefix = "/vlpground";
  std::string frame_id = "vehicle";  // frame of the points' pose, the ground and the image
  // Sensor pose in `frame_id`: points are sent in the sensor frame with this pose (the
  // detector's extrinsics, so points and planes line up).
  Extrinsics extrinsics;
  float image_max_range_m = 60.0f;  // range image brightness fades to this range

  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

/// Receives one encoded message: channel index, log time (ns since epoch), bytes (valid
/// only during the call).
using MessageSink = std::function<void(std::size_t, std::int64_t, std::span<const std::byte>)>;

class FrameEncoder {
 public:
  explicit FrameEncoder(FrameEncoderConfig config = {});
  ~FrameEncoder();
  FrameEncoder(FrameEncoder&&) noexcept;
  FrameEncoder& operator=(FrameEncoder&&) noexcept;

  [[nodiscard]] const std::vector<ChannelSpec>& channels() const;
  [[nodiscard]] const FrameEncoderConfig& config() const;

  /// Encodes one labelled frame into the messages of the frame channels in `wanted`
  /// (points, ground, range image) and hands each to `sink`, stamped with the frame's
  /// first firing time. Buffers are reused: no heap allocation after the first frames.
  void encode(const LabelledFrame& frame, const MessageSink& sink,
              ChannelMask wanted = kAllChannels);

  /// Encodes the status message (call about once a second; the frame rate is measured
  /// between calls) and hands it to `sink` on kStatusChannel.
  void encode_status(const PipelineStats& stats, std::int64_t log_time_ns,
                     const MessageSink& sink);

  /// Remembers the latest position packet for the status (PPS, GPRMC fix).
  void note_position(const PositionPacket& packet);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground::viz
