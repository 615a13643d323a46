#include "status_encoder.hpp"

#include <nlohmann/json.hpp>

namespace vlpground::viz::detail {
namespace {

using nlohmann::json;

json latency_json(const LatencyStats& s) {
  return {{"samples", s.samples}, {"p50_ms", s.p50_ms}, {"p99_ms", s.p99_ms},
          {"max_ms", s.max_ms},   {"mean_ms", s.mean_ms}};
}

json gps_json(const PositionPacket* p) {
  if (p == nullptr) return {{"position_packets", false}, {"pps", "absent"}, {"gprmc", "absent"}};
  json j{{"position_packets", true},
         {"pps", pps_name(p->pps)},
         {"gprmc", p->gprmc.parsed ? (p->gprmc.valid ? "valid" : "void") : "absent"}};
  if (p->gprmc.parsed && p->gprmc.valid) {
    j["latitude_deg"] = p->gprmc.latitude_deg;
    j["longitude_deg"] = p->gprmc.longitude_deg;
    j["speed_knots"] = p->gprmc.speed_knots;
  }
  return j;
}

}  // namespace

const char* const kStatusJsonSchema = R"({
  "title": "vlpground.Status",
  "type": "object",
  "properties": {
    "frames": {"type": "object", "properties": {
      "assembled": {"type": "integer"}, "delivered": {"type": "integer"},
      "dropped": {"type": "integer"}, "incomplete": {"type": "integer"}}},
    "frame_rate_hz": {"type": "number", "description": "frames delivered per second since the previous status"},
    "returns": {"type": "integer"},
    "ground_returns": {"type": "integer"},
    "detect": {"$ref": "#/$defs/latency", "description": "GroundDetector::detect time per frame"},
    "latency": {"$ref": "#/$defs/latency", "description": "last packet of a rotation received -> callback"},
    "packets": {"type": "object", "properties": {
      "data": {"type": "integer"}, "position": {"type": "integer"}, "lost": {"type": "integer"},
      "skipped": {"type": "integer"}, "kernel_drops": {"type": "integer"}}},
    "gps": {"type": "object", "properties": {
      "position_packets": {"type": "boolean"},
      "pps": {"enum": ["absent", "synchronizing", "locked", "error"]},
      "gprmc": {"enum": ["absent", "void", "valid"]},
      "latitude_deg": {"type": "number"}, "longitude_deg": {"type": "number"},
      "speed_knots": {"type": "number"}}},
    "progress": {"type": "number", "description": "fraction of the capture read, -1 live"},
    "elapsed_s": {"type": "number"},
    "live": {"type": "boolean"},
    "finished": {"type": "boolean"}
  },
  "$defs": {"latency": {"type": "object", "properties": {
    "samples": {"type": "integer"}, "p50_ms": {"type": "number"}, "p99_ms": {"type": "number"},
    "max_ms": {"type": "number"}, "mean_ms": {"type": "number"}}}}
})";

void StatusEncoder::note_position(const PositionPacket& packet) {
  std::lock_guard lock(position_mutex_);
  position_ = packet;
  have_position_ = true;
}

std::span<const std::byte> StatusEncoder::encode(const PipelineStats& s) {
  double rate_hz = 0.0;  // since the previous call (the first: since the start)
  if (s.elapsed_s > last_elapsed_s_ && s.frames_delivered >= last_delivered_) {
    rate_hz = static_cast<double>(s.frames_delivered - last_delivered_) /
              (s.elapsed_s - last_elapsed_s_);
  }
  last_delivered_ = s.frames_delivered;
  last_elapsed_s_ = s.elapsed_s;

  const auto& c = s.capture;
  json gps;
  {
    std::lock_guard lock(position_mutex_);
    gps = gps_json(have_position_ ? &position_ : nullptr);
  }
  const json j{
      {"frames",
       {{"assembled", s.frames_assembled},
        {"delivered", s.frames_delivered},
        {"dropped", s.frames_dropped},
        {"incomplete", s.incomplete_frames}}},
      {"frame_rate_hz", rate_hz},
      {"returns", s.returns},
      {"ground_returns", s.ground_returns},
      {"detect", latency_json(s.detect)},
      {"latency", latency_json(s.latency)},
      {"packets",
       {{"data", c.source.data_packets},
        {"position", c.source.position_packets},
        {"lost", c.assembler.packets_lost},
        {"skipped", c.source.skipped() + c.assembler.skipped_upstream},
        {"kernel_drops", c.source.kernel_drops}}},
      {"gps", std::move(gps)},
      {"progress", s.progress},
      {"elapsed_s", s.elapsed_s},
      {"live", s.live},
      {"finished", s.finished},
  };
  text_ = j.dump();
  return std::as_bytes(std::span{text_.data(), text_.size()});
}

}  // namespace vlpground::viz::detail
