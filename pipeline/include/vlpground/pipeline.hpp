// vlpground::Pipeline: packets -> frames -> ground labels -> your program, on two threads.
//
// Acquisition thread: PacketSource -> PacketDecoder -> RotationAssembler (a CaptureReader).
// Detection thread: GroundDetector, then delivery. The two are joined by a bounded queue of
// preallocated frames from a pool; nothing is allocated per frame in steady state.
//
// Two ways to receive frames, both as LEASES (std::shared_ptr<const LabelledFrame>): the
// frame stays valid and unchanged while a copy of its lease lives, and returns to the pool
// when the last copy goes (no copy of the ~4 MB frame, no allocation):
// - pull: call next(timeout) from your own thread (executors, cyclic tasks). Used when no
//   frame callback is set before start().
// - push: on_frame(const LabelledFrame&) (valid during the call) or on_frame_lease(lease)
//   (keep it as long as you like), called on the detection thread.
// A program may hold up to PipelineConfig::lease_frames frames at once without slowing the
// pipeline. Holding more takes frames the pipeline needs: then live sources drop the oldest
// frame waiting for delivery (counted in frames_dropped), replay waits for a lease to go.
//
// Backpressure (PipelineConfig::backpressure): live sources drop the OLDEST pending frame when
// the detector falls behind (counted in PipelineStats::frames_dropped and reported through the
// diagnostics callback); pcap replay blocks the reader instead, so no frame is lost.
//
// Thread-safety: start(), stop(), wait(), next() and stats() may be called from any thread;
// stop() also from inside a callback. wait() and the destructor must not be called from a
// callback. The frame callbacks run on the detection thread, the telemetry callback on the
// acquisition thread, the diagnostics callback on either (calls are serialised). A lease may
// be read and released on any thread, also after the Pipeline is gone.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/driver/position_packet.hpp"
#include "vlpground/driver/rotation_assembler.hpp"
#include "vlpground/frame.hpp"

namespace vlpground {

enum class Backpressure : std::uint8_t {
  automatic,    // drop_oldest for live sources, block for replay
  block,        // the reader waits for the detector: no frame lost
  drop_oldest,  // the oldest pending frame is dropped (counted) to make room
};

struct PipelineConfig {
  // The source: a pcap file when `pcap` is set, else a UDP socket (`udp`). Ignored when a
  // PacketSource is handed to the Pipeline constructor.
  std::optional<PcapSourceConfig> pcap;
  UdpSourceConfig udp;
  DecoderConfig decoder;
  AssemblerConfig assembler;
  DetectorConfig detector;

  Backpressure backpressure = Backpressure::automatic;
  int queue_frames = 4;          // pending frames between the two threads (>= 1)
  int lease_frames = 2;          // frames the program may hold (leases, or ready for next())
  std::uint64_t max_frames = 0;  // stop after delivering this many frames; 0 = no limit
  int read_timeout_ms = 200;     // how often the reader wakes up when no packet arrives
  // Which sensor this pipeline serves, copied onto every LabelledFrame (MultiPipeline sets
  // them; a single-sensor program may name its sensor too).
  std::string sensor_name;
  std::uint32_t sensor_index = 0;

  /// Throws std::invalid_argument with a clear message (also validates the sub-configs).
  void validate() const;
};

/// Time from the arrival of a rotation's last packet (FrameMeta::completed_receive_ns) to
/// the start of its callback, and detector time per frame. Percentiles come from a fixed
/// histogram of 10 us bins up to 500 ms (exact to 10 us).
struct LatencyStats {
  std::uint64_t samples = 0;
  double p50_ms = 0, p99_ms = 0, max_ms = 0, mean_ms = 0;
};

struct PipelineStats {
  std::uint64_t frames_assembled = 0;  // frames produced by the reader (counted once queued)
  std::uint64_t frames_delivered = 0;  // callbacks invoked (exception or not)
  std::uint64_t frames_dropped = 0;    // dropped by the drop-oldest policy
  std::uint64_t callback_exceptions = 0;
  std::uint64_t incomplete_frames = 0;  // delivered frames with meta.complete == false
  std::uint64_t returns = 0;            // valid returns in delivered frames (all layers)
  std::uint64_t ground_returns = 0;
  CaptureCounters capture;  // source, decoder and assembler counters
  LatencyStats latency;     // completed_receive_ns -> callback (frames ended by silence excluded)
  // Frames ended by the silence timeout (FrameEnd::silence, e.g. the last one of a live run)
  // wait for the timeout before delivery: counted here, not in `latency`.
  std::uint64_t silence_frames = 0;
  double silence_latency_max_ms = 0;
  LatencyStats detect;      // GroundDetector::detect
  double progress = -1.0;   // fraction of the input read (replay), -1 live
  double elapsed_s = 0.0;   // since start()
  bool live = false;
  bool finished = false;  // both threads ended
};

/// Timings of one delivered frame.
struct FrameTimings {
  double detect_ms = 0;   // GroundDetector::detect
  double latency_ms = 0;  // completed_receive_ns -> callback (0 when the stamp is unknown)
};

/// One delivered rotation with its labels. Owned by the pipeline's pool; reached through a
/// lease (std::shared_ptr<const LabelledFrame>) or a callback reference.
struct LabelledFrame {
  /// Storage for frames of `capacity_columns` (allocates; the pipeline does it once).
  explicit LabelledFrame(int capacity_columns = kDefaultFrameCapacity);

  Frame frame;          // range image + per-column data + FrameMeta
  GroundResult ground;  // labels, heights, the four planes, partition centre, timings
  FrameTimings timings;
  std::uint64_t delivered_index = 0;  // 0, 1, 2, ... in delivery order (gaps in
                                      // meta.sequence mean dropped frames)
  std::string sensor_name;            // PipelineConfig::sensor_name (MultiPipeline: the
  std::uint32_t sensor_index = 0;     //   sensor's name and index in its config)
};

/// A frame held by the program: valid and unchanged while any copy lives.
using FrameLease = std::shared_ptr<const LabelledFrame>;

enum class DiagnosticKind : std::uint8_t {
  warning,             // from the decoder / reader (once per distinct warning)
  frame_dropped,       // drop-oldest policy dropped a pending frame
  callback_exception,  // the frame callback threw; the pipeline goes on
  source_error,        // the reader failed (exception); input ends
  finished,            // input ended or stop() was requested; final counters follow
};

struct Diagnostic {
  DiagnosticKind kind = DiagnosticKind::warning;
  std::string message;
  PipelineStats stats;  // snapshot of the counters at the time of the event
};

using FrameCallback = std::function<void(const LabelledFrame&)>;
using FrameLeaseCallback = std::function<void(FrameLease)>;
using TelemetryCallback = std::function<void(const PositionPacket&)>;
using DiagnosticsCallback = std::function<void(const Diagnostic&)>;

class Pipeline {
 public:
  /// Validates `config` (std::invalid_argument). The source is opened by start().
  explicit Pipeline(PipelineConfig config);
  /// Uses `source` instead of the one described by `config` (tests, custom transports).
  Pipeline(PipelineConfig config, std::unique_ptr<PacketSource> source);
  /// Stops and joins both threads.
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Set callbacks before start(). With either frame callback set, frames go to the
  // callback(s) (on_frame first); without, to next().
  void on_frame(FrameCallback callback);
  /// Like on_frame, with the frame's lease: keep it to use the frame after the call.
  void on_frame_lease(FrameLeaseCallback callback);
  void on_telemetry(TelemetryCallback callback);
  void on_diagnostics(DiagnosticsCallback callback);

  /// Opens the source (std::runtime_error with a one-line reason when it cannot) and starts
  /// both threads. Throws std::logic_error when called twice.
  void start();
  /// Asks both threads to end; returns at once. Pending frames are discarded. Idempotent.
  void stop();
  /// Blocks until the input ends and every pending frame was delivered, or until stop().
  void wait();
  /// Waits at most `timeout_ms`; returns true when the pipeline has finished.
  bool wait_for(int timeout_ms);

  /// Pull API: the next labelled frame, oldest first, waiting up to `timeout`; empty on
  /// timeout or at the end of the input (at_end() tells which). Allocation-free. Throws
  /// std::logic_error before start() or when a frame callback is set.
  FrameLease next(std::chrono::milliseconds timeout);
  /// True once the input ended (or stop() was called) and next() has handed out every frame.
  [[nodiscard]] bool at_end() const;

  [[nodiscard]] PipelineStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground
