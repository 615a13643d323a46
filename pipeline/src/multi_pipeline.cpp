#include "vlpground/multi_pipeline.hpp"

#include <atomic>
#include <charconv>
#include <cstddef>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "vlpground/driver/packet_queue_source.hpp"

namespace vlpground {
namespace {

bool valid_name(std::string_view name) {
  if (name.empty() || name.size() > 32) return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

[[noreturn]] void bad_spec(std::string_view spec, const std::string& why) {
  throw std::invalid_argument("sensor '" + std::string(spec) + "': " + why +
                              " (expected NAME=IP[:PORT][@x,y,z,roll,pitch,yaw])");
}

double parse_double(std::string_view text, std::string_view spec) {
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) {
    bad_spec(spec, "'" + std::string(text) + "' is not a number");
  }
  return value;
}

Extrinsics parse_pose(std::string_view text, std::string_view spec) {
  double v[6];
  std::size_t count = 0;
  while (true) {
    const std::size_t comma = text.find(',');
    if (count == 6) bad_spec(spec, "the pose needs exactly 6 numbers");
    v[count++] = parse_double(text.substr(0, comma), spec);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  if (count != 6) bad_spec(spec, "the pose needs exactly 6 numbers");
  return {v[0], v[1], v[2], v[3], v[4], v[5]};
}

std::uint16_t parse_port(std::string_view text, std::string_view spec) {
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value == 0 || value > 65535) {
    bad_spec(spec, "port '" + std::string(text) + "' is not in 1..65535");
  }
  return static_cast<std::uint16_t>(value);
}

}  // namespace

SensorConfig parse_sensor_spec(std::string_view spec, const SensorConfig& defaults) {
  SensorConfig sensor = defaults;
  const std::size_t equals = spec.find('=');
  if (equals == std::string_view::npos) bad_spec(spec, "no '='");
  sensor.name = std::string(spec.substr(0, equals));
  if (!valid_name(sensor.name)) {
    bad_spec(spec, "the name must be 1-32 letters, digits, '_', '-' or '.'");
  }
  std::string_view rest = spec.substr(equals + 1);
  const std::size_t at = rest.find('@');
  if (at != std::string_view::npos) {
    sensor.extrinsics = parse_pose(rest.substr(at + 1), spec);
    rest = rest.substr(0, at);
  }
  if (rest.empty()) bad_spec(spec, "no address");
  if (rest.front() == '[') {  // [IPv6] or [IPv6]:PORT
    const std::size_t close = rest.find(']');
    if (close == std::string_view::npos) bad_spec(spec, "no ']' after the IPv6 address");
    sensor.address = std::string(rest.substr(1, close - 1));
    const std::string_view after = rest.substr(close + 1);
    if (!after.empty()) {
      if (after.front() != ':') bad_spec(spec, "':PORT' expected after ']'");
      sensor.data_port = parse_port(after.substr(1), spec);
    }
  } else if (rest.find(':') != rest.rfind(':')) {  // a bare IPv6 address, no port
    sensor.address = std::string(rest);
  } else {
    const std::size_t colon = rest.find(':');
    sensor.address = std::string(rest.substr(0, colon));
    if (colon != std::string_view::npos) sensor.data_port = parse_port(rest.substr(colon + 1), spec);
  }
  return sensor;
}

namespace {

UdpRouterConfig router_config(const MultiPipelineConfig& c) {
  UdpRouterConfig r;
  r.bind_address = c.bind_address;
  r.multicast_group = c.multicast_group;
  r.reuse_address = c.reuse_address;
  r.receive_buffer_bytes = c.receive_buffer_bytes;
  for (const SensorConfig& s : c.sensors) r.sensors.push_back({s.address, s.data_port, s.position_port});
  return r;
}

PipelineConfig sensor_pipeline_config(const MultiPipelineConfig& c, std::size_t i) {
  PipelineConfig p = c.pipeline;
  p.detector.extrinsics = c.sensors[i].extrinsics;
  p.sensor_name = c.sensors[i].name;
  p.sensor_index = static_cast<std::uint32_t>(i);
  return p;
}

}  // namespace

void MultiPipelineConfig::validate() const {
  if (sensors.empty()) throw std::invalid_argument("no sensor configured");
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    if (!valid_name(sensors[i].name)) {
      throw std::invalid_argument("sensor name '" + sensors[i].name +
                                  "': 1-32 letters, digits, '_', '-' or '.'");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (sensors[j].name == sensors[i].name) {
        throw std::invalid_argument("two sensors are named '" + sensors[i].name + "'");
      }
    }
  }
  if (packet_queue < 2 || packet_queue > 1'000'000) {
    throw std::invalid_argument("packet_queue must be in [2, 1000000], got " +
                                std::to_string(packet_queue));
  }
  router_config(*this).validate();
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    try {
      PipelineConfig p = sensor_pipeline_config(*this, i);
      p.pcap.reset();
      p.udp = {};  // the router receives; the per-sensor UDP settings are unused
      p.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("sensor '" + sensors[i].name + "': " + e.what());
    }
  }
}

struct MultiPipeline::Impl {
  explicit Impl(MultiPipelineConfig c) : config(std::move(c)) {
    PushSourceConfig queue;
    queue.capacity_packets = config.packet_queue;
    for (std::size_t i = 0; i < config.sensors.size(); ++i) {
      auto source = std::make_unique<PacketQueueSource>(queue);
      queues.push_back(source.get());
      pipelines.push_back(
          std::make_unique<Pipeline>(sensor_pipeline_config(config, i), std::move(source)));
    }
    after_end.resize(config.sensors.size());
  }

  MultiPipelineConfig config;
  std::vector<PacketQueueSource*> queues;  // owned by the pipelines
  std::vector<std::unique_ptr<Pipeline>> pipelines;
  std::unique_ptr<UdpRouter> router;
  std::thread router_thread;
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> router_done{false};
  std::atomic<bool> started{false};
  std::mutex start_mutex;  // start() against stop() from other threads
  std::mutex diagnostics_mutex;
  SensorDiagnosticsCallback diagnostics_cb;

  mutable std::mutex counters_mutex;
  UdpRouterCounters router_counters;  // a copy, refreshed by the router thread
  std::vector<std::uint64_t> after_end;  // packets for a sensor whose pipeline had ended

  void publish_counters() {
    std::lock_guard lock(counters_mutex);
    router_counters = router->counters();  // same sizes: no allocation after the first
  }

  void route() {
    RoutedPacket packet;
    std::uint32_t since_publish = 0;
    while (!stop_requested) {
      const SourceStatus status = router->next(packet, config.pipeline.read_timeout_ms);
      if (status == SourceStatus::stopped) break;
      if (status == SourceStatus::packet) {
        const PushResult result =
            queues[packet.sensor]->push(std::as_bytes(packet.packet.bytes), packet.packet.receive_ns,
                                        packet.packet.kind, packet.packet.source);
        if (result == PushResult::closed) {
          std::lock_guard lock(counters_mutex);
          ++after_end[packet.sensor];
        }
        if (++since_publish < 64) continue;
      } else if (all_pipelines_ended()) {
        break;  // every sensor reached max_frames
      }
      since_publish = 0;
      publish_counters();
    }
    publish_counters();
    for (PacketQueueSource* queue : queues) queue->close();
    router_done = true;
  }

  bool all_pipelines_ended() {
    for (const auto& p : pipelines) {
      if (!p->stats().finished) return false;
    }
    return true;
  }
};

MultiPipeline::MultiPipeline(MultiPipelineConfig config) {
  config.validate();
  impl_ = std::make_unique<Impl>(std::move(config));
}

MultiPipeline::~MultiPipeline() {
  stop();
  for (auto& p : impl_->pipelines) p->stop();  // do not wait for the queued packets
  if (impl_->router_thread.joinable()) impl_->router_thread.join();
  impl_->pipelines.clear();  // each stops and joins its threads
}

void MultiPipeline::on_frame(FrameCallback callback) {
  for (auto& p : impl_->pipelines) p->on_frame(callback);
}

void MultiPipeline::on_frame_lease(FrameLeaseCallback callback) {
  for (auto& p : impl_->pipelines) p->on_frame_lease(callback);
}

void MultiPipeline::on_diagnostics(SensorDiagnosticsCallback callback) {
  impl_->diagnostics_cb = std::move(callback);
  for (std::size_t i = 0; i < impl_->pipelines.size(); ++i) {
    impl_->pipelines[i]->on_diagnostics([this, i](const Diagnostic& d) {
      std::lock_guard lock(impl_->diagnostics_mutex);
      if (impl_->diagnostics_cb) impl_->diagnostics_cb(i, d);
    });
  }
}

void MultiPipeline::on_telemetry(
    std::function<void(std::size_t sensor, const PositionPacket&)> callback) {
  for (std::size_t i = 0; i < impl_->pipelines.size(); ++i) {
    if (!callback) continue;
    impl_->pipelines[i]->on_telemetry([callback, i](const PositionPacket& p) { callback(i, p); });
  }
}

void MultiPipeline::start() {
  std::lock_guard lock(impl_->start_mutex);  // stop() from another thread waits for the router
  if (impl_->started) throw std::logic_error("MultiPipeline::start() called twice");
  impl_->router = open_udp_router(router_config(impl_->config));  // throws: not started
  impl_->started = true;
  impl_->publish_counters();
  for (auto& p : impl_->pipelines) p->start();
  impl_->router_thread = std::thread([this] { impl_->route(); });
}

void MultiPipeline::stop() {
  std::lock_guard lock(impl_->start_mutex);
  impl_->stop_requested = true;
  if (impl_->router) impl_->router->request_stop();  // the router then closes the queues
}

void MultiPipeline::wait() {
  if (!impl_->started) return;
  if (impl_->router_thread.joinable()) impl_->router_thread.join();
  for (auto& p : impl_->pipelines) p->wait();
}

bool MultiPipeline::wait_for(int timeout_ms) {
  if (!impl_->started) return true;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (auto& p : impl_->pipelines) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (!p->wait_for(static_cast<int>(std::max<std::int64_t>(left.count(), 0)))) return false;
  }
  // Every pipeline ended (after stop() or at max_frames): the router has nothing to feed.
  impl_->router->request_stop();
  if (impl_->router_thread.joinable()) impl_->router_thread.join();
  return true;
}

std::size_t MultiPipeline::sensor_count() const { return impl_->pipelines.size(); }

const SensorConfig& MultiPipeline::sensor_config(std::size_t sensor) const {
  return impl_->config.sensors.at(sensor);
}

Pipeline& MultiPipeline::sensor(std::size_t sensor) { return *impl_->pipelines.at(sensor); }

MultiPipelineStats MultiPipeline::stats() const {
  MultiPipelineStats s;
  s.finished = impl_->started && impl_->router_done;
  {
    std::lock_guard lock(impl_->counters_mutex);
    s.router = impl_->router_counters;
  }
  for (std::size_t i = 0; i < impl_->pipelines.size(); ++i) {
    SensorStats sensor;
    sensor.name = impl_->config.sensors[i].name;
    sensor.pipeline = impl_->pipelines[i]->stats();
    sensor.queue_full = impl_->queues[i]->queue_full_count();
    {
      std::lock_guard lock(impl_->counters_mutex);
      sensor.after_end = impl_->after_end[i];
    }
    s.finished = s.finished && sensor.pipeline.finished;
    s.sensors.push_back(std::move(sensor));
  }
  return s;
}

}  // namespace vlpground
