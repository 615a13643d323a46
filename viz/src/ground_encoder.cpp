#include "ground_encoder.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "proto_util.hpp"

namespace vlpground::viz::detail {
namespace {

constexpr int kCorners = 4;
constexpr float kOutlineLiftM = 0.02f;  // outlines just above the patch, so they stay visible

// Height of plane n . p + d = 0 at (x, y); n.z > 0 for detector planes (bounded if not).
double plane_z(const Plane& p, double x, double y) {
  const double nz = std::max(static_cast<double>(p.nz), 1e-3);
  return -(p.nx * x + p.ny * y + p.d) / nz;
}

void set_corners(google::protobuf::RepeatedPtrField<foxglove::Point3>& points,
                 const GroundSegment& s, float lift_m) {
  const double xs[kCorners] = {s.x_min_m, s.x_max_m, s.x_max_m, s.x_min_m};
  const double ys[kCorners] = {s.y_min_m, s.y_min_m, s.y_max_m, s.y_max_m};
  for (int i = 0; i < kCorners; ++i) {
    auto& p = points[i];
    p.set_x(xs[i]);
    p.set_y(ys[i]);
    p.set_z(plane_z(s.plane, xs[i], ys[i]) + lift_m);
  }
}

// Frame facts carried as entity metadata (the web page shows the frame number from it).
enum Meta : int { kFrame, kDelivered, kComplete, kDetectMs, kGroundReturns, kObstacleReturns, kMetaCount };
constexpr const char* kMetaKeys[kMetaCount] = {"frame",     "delivered",     "complete",
                                               "detect_ms", "ground_returns", "obstacle_returns"};

// Writes `value` into `out` in place (no allocation once the string has grown).
void set_number(std::string& out, std::uint64_t value) {
  char text[24];
  out.assign(text, std::to_chars(text, text + sizeof text, value).ptr);
}
void set_number(std::string& out, double value) {
  char text[48];
  out.assign(text, std::to_chars(text, text + sizeof text, value, std::chars_format::fixed, 3).ptr);
}

}  // namespace

GroundEncoder::GroundEncoder(const FrameEncoderConfig& config) {
  auto* entity = message_.add_entities();
  entity->set_frame_id(config.frame_id);
  entity->set_id("ground");
  for (const char* key : kMetaKeys) {
    auto* kv = entity->add_metadata();
    kv->set_key(key);
    kv->mutable_value()->reserve(24);
  }
  for (std::size_t s = 0; s < std::tuple_size_v<decltype(GroundResult::segments)>; ++s) {
    auto* patch = entity->add_triangles();
    set_identity(*patch->mutable_pose());
    for (int i = 0; i < kCorners; ++i) patch->add_points();
    for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) patch->add_indices(i);
    auto* outline = entity->add_lines();
    outline->set_type(foxglove::LinePrimitive::LINE_LOOP);
    set_identity(*outline->mutable_pose());
    outline->set_thickness(2.0);
    outline->set_scale_invariant(true);
    for (int i = 0; i < kCorners; ++i) outline->add_points();
    set_color(*outline->mutable_color(), 0.9, 0.9, 0.9, 0.8);
  }
}

std::span<const std::byte> GroundEncoder::encode(const LabelledFrame& lf) {
  auto& entity = *message_.mutable_entities(0);
  set_time(*entity.mutable_timestamp(), lf.frame.meta.first_time_ns);
  auto& meta = *entity.mutable_metadata();
  set_number(*meta[kFrame].mutable_value(), lf.frame.meta.sequence);
  set_number(*meta[kDelivered].mutable_value(), lf.delivered_index);
  meta[kComplete].mutable_value()->assign(lf.frame.meta.complete ? "true" : "false");
  set_number(*meta[kDetectMs].mutable_value(), lf.timings.detect_ms);
  set_number(*meta[kGroundReturns].mutable_value(), lf.ground.ground_returns);
  set_number(*meta[kObstacleReturns].mutable_value(), lf.ground.obstacle_returns);
  const auto& segments = lf.ground.segments;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const GroundSegment& g = segments[s];
    const int i = static_cast<int>(s);
    auto& patch = *entity.mutable_triangles(i);
    set_corners(*patch.mutable_points(), g, 0.0f);
    if (g.has_ground) {
      set_color(*patch.mutable_color(), 0.15, 0.75, 0.25, 0.35);
    } else if (g.inherited) {
      set_color(*patch.mutable_color(), 0.95, 0.7, 0.1, 0.3);
    } else {
      set_color(*patch.mutable_color(), 0.5, 0.5, 0.5, 0.0);
    }
    set_corners(*entity.mutable_lines(i)->mutable_points(), g, kOutlineLiftM);
  }
  return serialize(message_, buffer_);
}

}  // namespace vlpground::viz::detail
