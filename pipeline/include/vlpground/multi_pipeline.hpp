// vlpground::MultiPipeline: several sensors in one process. Cars carry two to five VLP-16s,
// often all sending to port 2368 and told apart only by their source address.
//
//   UDP sockets (one per distinct port) -> UdpRouter (by source address and port)
//     -> one PacketQueueSource per sensor -> one Pipeline per sensor (assembler, detector
//        with the sensor's extrinsics, frame pool) -> your callbacks or sensor(i).next()
//
// Every labelled frame names its sensor (LabelledFrame::sensor_name / sensor_index). A
// datagram from an address no sensor has is counted (MultiPipelineStats::router.unknown_source),
// never silently dropped; so is a packet refused by a full per-sensor queue (queue_full).
//
// Thread-safety: as Pipeline. The frame callbacks run on each sensor's detection thread, so
// frames of DIFFERENT sensors may be delivered concurrently; the diagnostics callback is
// serialised over all sensors.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "vlpground/driver/udp_router.hpp"
#include "vlpground/pipeline.hpp"

namespace vlpground {

struct SensorConfig {
  std::string name;     // unique; letters, digits, '_', '-', '.' (used in file names)
  std::string address;  // the sensor's IPv4/IPv6 address (empty = any; one sensor only)
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;  // 0 = ignore its position packets
  Extrinsics extrinsics;               // the sensor's pose in the vehicle (m, deg)
};

/// Parses "NAME=IP[:PORT][@x,y,z,roll,pitch,yaw]" (IPv6 in brackets with a port:
/// "rear=[fe80::1]:2369"). What the spec leaves out (data port, pose; the position port
/// always) comes from `defaults`. Throws std::invalid_argument naming the bad part.
SensorConfig parse_sensor_spec(std::string_view spec, const SensorConfig& defaults = {});

struct MultiPipelineConfig {
  std::vector<SensorConfig> sensors;
  // Reception, shared by all sensors (see UdpRouterConfig).
  std::string bind_address = "0.0.0.0";
  std::string multicast_group;
  bool reuse_address = false;
  int receive_buffer_bytes = 8 * 1024 * 1024;  // per socket (several sensors share one)
  int packet_queue = 2048;  // packets waiting per sensor between router and decoder (>= 2)
  /// Decoder, assembler, detector, backpressure, queue and lease sizes, max_frames (per
  /// sensor) for every sensor. Its source fields are ignored; detector.extrinsics,
  /// sensor_name and sensor_index are set from `sensors`.
  PipelineConfig pipeline;

  /// Throws std::invalid_argument with a clear message (no sensor, bad or duplicate names,
  /// routing conflicts, the pipeline settings).
  void validate() const;
};

struct SensorStats {
  std::string name;
  PipelineStats pipeline;  // pipeline.capture.source counts what the router pushed in
  std::uint64_t queue_full = 0;  // packets refused because the sensor's queue was full
  std::uint64_t after_end = 0;   // packets that came after the sensor's pipeline had ended
};

struct MultiPipelineStats {
  UdpRouterCounters router;  // datagrams read, per sensor and unknown sources, kernel drops
  std::vector<SensorStats> sensors;
  bool finished = false;  // router and every pipeline ended
};

/// Diagnostics of one sensor's pipeline; `sensor` indexes MultiPipelineConfig::sensors.
using SensorDiagnosticsCallback = std::function<void(std::size_t sensor, const Diagnostic&)>;

class MultiPipeline {
 public:
  /// Validates `config` (std::invalid_argument). Sockets are opened by start().
  explicit MultiPipeline(MultiPipelineConfig config);
  ~MultiPipeline();
  MultiPipeline(const MultiPipeline&) = delete;
  MultiPipeline& operator=(const MultiPipeline&) = delete;

  // Set callbacks before start(). Without a frame callback, pull with sensor(i).next().
  void on_frame(FrameCallback callback);
  void on_frame_lease(FrameLeaseCallback callback);
  void on_diagnostics(SensorDiagnosticsCallback callback);
  /// Position packets of sensor `sensor`.
  void on_telemetry(std::function<void(std::size_t sensor, const PositionPacket&)> callback);

  /// Binds the sockets (std::runtime_error with a one-line reason) and starts the router and
  /// every pipeline. Throws std::logic_error when called twice.
  void start();
  /// Stops receiving and returns at once; the packets already queued (at most packet_queue
  /// per sensor) are still decoded and their frames delivered, then every pipeline ends.
  /// Idempotent; callable from a callback.
  void stop();
  /// Blocks until everything has ended (after stop(), or once every sensor reached
  /// max_frames).
  void wait();
  /// Waits at most `timeout_ms`; true when everything has ended.
  bool wait_for(int timeout_ms);

  [[nodiscard]] std::size_t sensor_count() const;
  [[nodiscard]] const SensorConfig& sensor_config(std::size_t sensor) const;
  /// The pipeline of one sensor (for next() in pull mode, or its stats()).
  Pipeline& sensor(std::size_t sensor);

  [[nodiscard]] MultiPipelineStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground
