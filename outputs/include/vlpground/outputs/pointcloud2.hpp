// The sensor_msgs/PointCloud2 byte layout of a labelled frame, shared by every front-end that
// emits PointCloud2 (the ROS 2 publisher, recorders). Only the layout: no ROS or DDS types.
//
// Point record (24 bytes, host byte order, every field naturally aligned):
//   offset  0 x          float32  m, sensor frame (x forward, y left, z up); NaN if no return
//   offset  4 y          float32
//   offset  8 z          float32
//   offset 12 intensity  float32  calibrated reflectivity 0..255 (0 if no return)
//   offset 16 ring       uint16   0 = lowest beam ... 15 = highest
//   offset 18 label      uint8    0 none (no return) / 1 ground / 2 obstacle
//   offset 19 return     uint8    0 strongest (or the only) return, 1 last return (dual)
//   offset 20 time       float32  s since the frame's first firing (FrameMeta::first_time_ns)
// x y z intensity ring time match ros-drivers/velodyne's PointXYZIRT by name and type.
//
// Organized cloud: height 16 (32 in dual mode: rows 0-15 the strongest return, rows 16-31 the
// last return, each bottom-up by ring), width = frame columns, is_dense false. Ground-only
// and obstacle-only clouds: height 1, width = point count, is_dense true, same record.
//
// Thread-safety: pure functions; the caller owns the output buffer.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::outputs {

/// sensor_msgs/PointField datatype constants.
enum class PointDatatype : std::uint8_t {
  int8 = 1,
  uint8 = 2,
  int16 = 3,
  uint16 = 4,
  int32 = 5,
  uint32 = 6,
  float32 = 7,
  float64 = 8,
};

struct PointFieldSpec {
  std::string_view name;
  std::uint32_t offset;
  PointDatatype datatype;
  std::uint32_t count;
};

inline constexpr std::uint32_t kPointStep = 24;

/// The `fields` of every cloud, in this order.
inline constexpr std::array<PointFieldSpec, 8> kPointFields{{
    {"x", 0, PointDatatype::float32, 1},
    {"y", 4, PointDatatype::float32, 1},
    {"z", 8, PointDatatype::float32, 1},
    {"intensity", 12, PointDatatype::float32, 1},
    {"ring", 16, PointDatatype::uint16, 1},
    {"time", 20, PointDatatype::float32, 1},
    {"label", 18, PointDatatype::uint8, 1},
    {"return", 19, PointDatatype::uint8, 1},
}};

/// PointCloud2 `is_bigendian`: the records are written in host byte order.
inline constexpr bool kBigEndian = std::endian::native == std::endian::big;

enum class CloudKind : std::uint8_t {
  organized,      // every cell, invalid ones with NaN coordinates
  ground_only,    // dense: returns labelled ground
  obstacle_only,  // dense: returns labelled obstacle
};

/// The PointCloud2 metadata of an encoded cloud; its data is `bytes()` long.
struct CloudShape {
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::uint32_t point_step = kPointStep;
  std::uint32_t row_step = 0;  // width * point_step
  bool is_dense = false;
  [[nodiscard]] std::size_t bytes() const {
    return static_cast<std::size_t>(row_step) * static_cast<std::size_t>(height);
  }
};

/// Bytes the largest cloud of `frame` needs (the organized one): a buffer this long fits
/// every CloudKind.
[[nodiscard]] std::size_t max_cloud_bytes(const Frame& frame);
/// The same bound for any frame of `capacity_columns` columns in dual mode.
[[nodiscard]] std::size_t max_cloud_bytes(int capacity_columns);

/// Writes the `kind` cloud of `frame` (labels from `ground`; cells without a label read 0)
/// into `out`, which must hold at least max_cloud_bytes(frame) bytes (std::invalid_argument
/// otherwise). Allocates nothing.
CloudShape encode_pointcloud2(const Frame& frame, const GroundResult& ground, CloudKind kind,
                              std::span<std::uint8_t> out);

}  // namespace vlpground::outputs
