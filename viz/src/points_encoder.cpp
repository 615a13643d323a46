#include "points_encoder.hpp"

#include <bit>
#include <cstring>

#include "proto_util.hpp"

namespace vlpground::viz::detail {
namespace {

struct PackedPoint {
  float x, y, z;
  std::uint8_t intensity, ring, label, layer;
};
static_assert(sizeof(PackedPoint) == kPointStride);
static_assert(std::endian::native == std::endian::little, "points are copied as little-endian");

void add_field(foxglove::PointCloud& m, const char* name, std::uint32_t offset,
               foxglove::PackedElementField::NumericType type) {
  auto* f = m.add_fields();
  f->set_name(name);
  f->set_offset(offset);
  f->set_type(type);
}

}  // namespace

PointsEncoder::PointsEncoder(const FrameEncoderConfig& config) {
  using F = foxglove::PackedElementField;
  message_.set_frame_id(config.frame_id);
  set_pose(*message_.mutable_pose(), config.extrinsics);
  message_.set_point_stride(kPointStride);
  add_field(message_, "x", offsetof(PackedPoint, x), F::FLOAT32);
  add_field(message_, "y", offsetof(PackedPoint, y), F::FLOAT32);
  add_field(message_, "z", offsetof(PackedPoint, z), F::FLOAT32);
  add_field(message_, "intensity", offsetof(PackedPoint, intensity), F::UINT8);
  add_field(message_, "ring", offsetof(PackedPoint, ring), F::UINT8);
  add_field(message_, "label", offsetof(PackedPoint, label), F::UINT8);
  add_field(message_, "return", offsetof(PackedPoint, layer), F::UINT8);
}

std::span<const std::byte> PointsEncoder::encode(const LabelledFrame& lf) {
  const Frame& frame = lf.frame;
  const GroundResult& ground = lf.ground;
  set_time(*message_.mutable_timestamp(), frame.meta.first_time_ns);

  const auto cells = static_cast<std::size_t>(frame.columns()) * kLasers;
  std::string& data = *message_.mutable_data();
  data.resize(cells * static_cast<std::size_t>(frame.layers()) * kPointStride);
  char* out = data.data();

  std::uint8_t ring_of_laser[kLasers] = {};
  for (int r = 0; r < kLasers; ++r)
    ring_of_laser[frame.laser_of_ring[r]] = static_cast<std::uint8_t>(r);
  const auto label_at = [&](int layer, std::size_t ground_cell) -> std::uint8_t {
    const auto& labels = ground.label[layer];
    return ground_cell < labels.size() ? labels[ground_cell] : 0;
  };

  std::size_t n = 0;
  for (int col = 0; col < frame.columns(); ++col) {
    for (int laser = 0; laser < kLasers; ++laser) {
      const int ring = ring_of_laser[laser];
      const std::size_t cell = frame.index(ring, col);
      const std::size_t ground_cell = static_cast<std::size_t>(ring) *
                                          static_cast<std::size_t>(ground.stride) +
                                      static_cast<std::size_t>(col);
      for (int l = 0; l < frame.layers(); ++l) {
        const ReturnLayer& layer = frame.layer[l];
        if (layer.valid[cell] == 0) continue;
        const PackedPoint p{layer.x_m[cell],        layer.y_m[cell],
                            layer.z_m[cell],        layer.intensity[cell],
                            static_cast<std::uint8_t>(ring), label_at(l, ground_cell),
                            static_cast<std::uint8_t>(l)};
        std::memcpy(out + n * kPointStride, &p, kPointStride);
        ++n;
      }
    }
  }
  data.resize(n * kPointStride);
  return serialize(message_, buffer_);
}

}  // namespace vlpground::viz::detail
