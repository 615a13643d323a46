#include "vlpground/viz/mcap_recorder.hpp"

#include <mutex>
#include <vector>

namespace vlpground::viz {

void McapRecorderConfig::validate() const {
  writer.validate();
  encoder.validate();
}

struct McapRecorder::Impl {
  explicit Impl(McapRecorderConfig c) : config(std::move(c)), encoder(config.encoder) {}

  McapRecorderConfig config;
  FrameEncoder encoder;
  mcap::Writer writer;
  std::vector<std::uint16_t> channel_ids;  // FrameEncoder channel index -> MCAP channel id
  MessageSink sink;
  mutable std::mutex mutex;
  std::int64_t last_frame_time_ns = 0;
  std::uint64_t frames = 0;

  void open(const std::string& path) {
    writer.open(path, config.writer);
    for (const ChannelSpec& spec : encoder.channels()) {
      const std::uint16_t schema = writer.add_schema(
          spec.schema_name, spec.schema_encoding,
          std::as_bytes(std::span(spec.schema.data(), spec.schema.size())));
      channel_ids.push_back(writer.add_channel(schema, spec.topic, spec.message_encoding));
    }
    sink = [this](std::size_t channel, std::int64_t log_time_ns, std::span<const std::byte> data) {
      const auto t = static_cast<std::uint64_t>(std::max<std::int64_t>(log_time_ns, 0));
      writer.write(channel_ids.at(channel), t, t, data);
    };
  }
};

McapRecorder::McapRecorder(const std::string& path, McapRecorderConfig config) {
  config.validate();
  impl_ = std::make_unique<Impl>(std::move(config));
  impl_->open(path);
}

McapRecorder::~McapRecorder() {
  try {
    close();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw
  }
}

void McapRecorder::record(const LabelledFrame& frame) {
  const std::lock_guard lock(impl_->mutex);
  impl_->encoder.encode(frame, impl_->sink);
  impl_->writer.flush();  // one chunk per frame: on disk before we return
  impl_->last_frame_time_ns = frame.frame.meta.first_time_ns;
  ++impl_->frames;
}

void McapRecorder::record_status(const PipelineStats& stats) {
  const std::lock_guard lock(impl_->mutex);
  // Before the first frame there is no capture time to stamp it with (a wall-clock stamp
  // would stretch a replay's timeline over years).
  if (!impl_->writer.is_open() || impl_->frames == 0) return;
  impl_->encoder.encode_status(stats, impl_->last_frame_time_ns, impl_->sink);
  impl_->writer.flush();
}

void McapRecorder::note_position(const PositionPacket& packet) {
  impl_->encoder.note_position(packet);
}

void McapRecorder::close() {
  const std::lock_guard lock(impl_->mutex);
  impl_->writer.close();
}

mcap::WriterStats McapRecorder::stats() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->writer.stats();
}

std::uint64_t McapRecorder::frames_recorded() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->frames;
}

}  // namespace vlpground::viz
