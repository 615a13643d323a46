// Geometry of one sensor: per-laser elevation, azimuth correction and vertical offset, and
// the ring (elevation-sorted row) of each laser. Built in for VLP-16 and Puck Hi-Res, or
// loaded from a ROS-velodyne-style calibration YAML.
//
// Thread-safety: immutable after construction; share freely.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "vlpground/types.hpp"

namespace vlpground {

struct LaserGeometry {
  double elevation_deg = 0.0;          // vertical angle (vert_correction)
  double azimuth_offset_deg = 0.0;     // rotational correction (rot_correction), usually 0
  double vertical_offset_m = 0.0;      // added to z (vert_offset_correction)
  double distance_correction_m = 0.0;  // added to every nonzero range (dist_correction)
  // Precomputed from the above.
  double cos_elevation = 1.0;
  double sin_elevation = 0.0;
  double cos_azimuth_offset = 1.0;
  double sin_azimuth_offset = 0.0;
};

struct SensorModel {
  Model model = Model::vlp16;
  std::array<LaserGeometry, kLasers> lasers{};        // indexed by laser id (firing order)
  std::array<std::uint8_t, kLasers> ring_of_laser{};  // 0 = lowest elevation
  std::array<std::uint8_t, kLasers> laser_of_ring{};
  double distance_resolution_m = 0.002;  // range unit of the packet (2 mm)
  std::string source = "built-in";       // "built-in", or the calibration file's path

  /// The manual's angles and offsets for `model`.
  static SensorModel builtin(Model model);

  /// Loads a calibration YAML in the format of the ROS velodyne driver (`lasers:` list with
  /// `laser_id`, `vert_correction`, `rot_correction`, `vert_offset_correction`, ... in
  /// radians / metres). Throws std::invalid_argument naming the file, line or field on any
  /// malformed or missing entry.
  static SensorModel from_calibration_file(const std::string& path, Model model);

  /// Recomputes the trigonometric caches and the ring permutation from the angles.
  void finalize();
};

}  // namespace vlpground
