#include "vlpground/outputs/pointcloud2.hpp"

#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace vlpground::outputs {
namespace {

// The record of the header comment; offsets checked against kPointFields below.
struct Record {
  float x, y, z, intensity;
  std::uint16_t ring;
  std::uint8_t label;
  std::uint8_t return_index;
  float time;
};
static_assert(sizeof(Record) == kPointStep);
static_assert(offsetof(Record, x) == kPointFields[0].offset);
static_assert(offsetof(Record, y) == kPointFields[1].offset);
static_assert(offsetof(Record, z) == kPointFields[2].offset);
static_assert(offsetof(Record, intensity) == kPointFields[3].offset);
static_assert(offsetof(Record, ring) == kPointFields[4].offset);
static_assert(offsetof(Record, time) == kPointFields[5].offset);
static_assert(offsetof(Record, label) == kPointFields[6].offset);
static_assert(offsetof(Record, return_index) == kPointFields[7].offset);

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Labels of one layer, or null when the result does not cover the frame (no detector ran).
const std::uint8_t* labels_of(const GroundResult& ground, const Frame& frame, int layer) {
  const auto& labels = ground.label[layer];
  const std::size_t needed =
      static_cast<std::size_t>(kLasers - 1) * static_cast<std::size_t>(ground.stride) +
      static_cast<std::size_t>(frame.columns());
  if (ground.stride < frame.columns() || labels.size() < needed) return nullptr;
  return labels.data();
}

// Visits every cell in cloud order (layer, ring bottom-up, column) as a Record.
template <typename Sink>
void for_each_record(const Frame& frame, const GroundResult& ground, Sink&& sink) {
  const int columns = frame.columns();
  const std::int64_t t0 = frame.meta.first_time_ns;
  for (int l = 0; l < frame.layers(); ++l) {
    const ReturnLayer& layer = frame.layer[l];
    const std::uint8_t* labels = labels_of(ground, frame, l);
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::int64_t laser_ns = frame.laser_of_ring[ring] * kFiringIntervalNs;
      const std::size_t row = frame.index(ring, 0);
      const std::size_t label_row =
          static_cast<std::size_t>(ring) * static_cast<std::size_t>(ground.stride);
      for (int col = 0; col < columns; ++col) {
        const std::size_t i = row + static_cast<std::size_t>(col);
        const bool valid = layer.valid[i] != 0;
        Record r;
        r.x = valid ? layer.x_m[i] : kNaN;
        r.y = valid ? layer.y_m[i] : kNaN;
        r.z = valid ? layer.z_m[i] : kNaN;
        r.intensity = valid ? static_cast<float>(layer.intensity[i]) : 0.f;
        r.ring = static_cast<std::uint16_t>(ring);
        r.label = valid && labels != nullptr ? labels[label_row + static_cast<std::size_t>(col)]
                                             : std::uint8_t{0};
        r.return_index = static_cast<std::uint8_t>(l);
        r.time = static_cast<float>(
            static_cast<double>(frame.column_time_ns[static_cast<std::size_t>(col)] - t0 +
                                laser_ns) *
            1e-9);
        sink(r);
      }
    }
  }
}

}  // namespace

std::size_t max_cloud_bytes(int capacity_columns) {
  return static_cast<std::size_t>(2 * kLasers) * static_cast<std::size_t>(capacity_columns) *
         kPointStep;
}

std::size_t max_cloud_bytes(const Frame& frame) {
  return static_cast<std::size_t>(frame.layers() * kLasers) *
         static_cast<std::size_t>(frame.columns()) * kPointStep;
}

CloudShape encode_pointcloud2(const Frame& frame, const GroundResult& ground, CloudKind kind,
                              std::span<std::uint8_t> out) {
  if (out.size() < max_cloud_bytes(frame)) {
    throw std::invalid_argument("encode_pointcloud2: buffer of " + std::to_string(out.size()) +
                                " bytes, the frame needs " +
                                std::to_string(max_cloud_bytes(frame)));
  }
  std::uint8_t* p = out.data();
  std::uint32_t points = 0;
  if (kind == CloudKind::organized) {
    for_each_record(frame, ground, [&](const Record& r) {
      std::memcpy(p, &r, kPointStep);
      p += kPointStep;
    });
    CloudShape shape;
    shape.height = static_cast<std::uint32_t>(frame.layers() * kLasers);
    shape.width = static_cast<std::uint32_t>(frame.columns());
    shape.row_step = shape.width * kPointStep;
    shape.is_dense = false;
    return shape;
  }
  const auto wanted = static_cast<std::uint8_t>(
      kind == CloudKind::ground_only ? GroundLabel::ground : GroundLabel::obstacle);
  for_each_record(frame, ground, [&](const Record& r) {
    if (r.label != wanted) return;
    std::memcpy(p, &r, kPointStep);
    p += kPointStep;
    ++points;
  });
  CloudShape shape;
  shape.height = 1;
  shape.width = points;
  shape.row_step = points * kPointStep;
  shape.is_dense = true;
  return shape;
}

}  // namespace vlpground::outputs
