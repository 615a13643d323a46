// vlpground::viz::McapRecorder: records the Foxglove channels of labelled frames
// (viz::FrameEncoder: points, ground, range image, status) to an MCAP file that Foxglove and
// Lichtblick open. Call record() from the pipeline's frame callback.
//
// One chunk per frame: each frame's messages reach the file (write(2)) before record()
// returns, so a crash or kill loses at most the frame being written; a file cut short reads
// sequentially (streaming readers) up to its last complete frame. close() adds the summary
// that makes the file seekable; a Ctrl-C handled by the caller (Pipeline::stop, then close)
// leaves a complete file.
//
// Times: every message is logged at its frame's first firing time (FrameMeta::first_time_ns);
// status messages at the last recorded frame's time, so replays keep the capture's timeline.
//
// Thread-safety: record() and record_status() may be called from different threads (the
// detection thread and a once-a-second stats thread); calls are serialised.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "vlpground/mcap/writer.hpp"
#include "vlpground/viz/channels.hpp"

namespace vlpground::viz {

struct McapRecorderConfig {
  mcap::WriterConfig writer;    // compression (zstd by default), chunk bound
  FrameEncoderConfig encoder;   // topics, frame id, extrinsics

  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

class McapRecorder {
 public:
  /// Creates `path` and writes the header, schemas and channels. Throws std::runtime_error
  /// (path and reason) when the file cannot be created, std::invalid_argument for a bad config.
  explicit McapRecorder(const std::string& path, McapRecorderConfig config = {});
  /// close(); errors there are swallowed (call close() to see them).
  ~McapRecorder();
  McapRecorder(const McapRecorder&) = delete;
  McapRecorder& operator=(const McapRecorder&) = delete;

  /// Encodes the frame's channels and writes them as one chunk. No heap allocation per frame
  /// once warmed up. Throws std::runtime_error when the file cannot be written.
  void record(const LabelledFrame& frame);
  /// Writes one status message (call about once a second).
  void record_status(const PipelineStats& stats);
  /// Remembers the latest position packet for the status (PPS, GPRMC fix).
  void note_position(const PositionPacket& packet);
  /// Writes the summary and footer and closes the file. Idempotent.
  void close();

  [[nodiscard]] mcap::WriterStats stats() const;
  [[nodiscard]] std::uint64_t frames_recorded() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground::viz
