// Analytic VLP-16 scenes for detector tests: 16 rings at -15..15 deg (ring 0 lowest) cast
// against a ground surface (flat, or a grade change), optional walls and boxes.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "vlpground/frame.hpp"

namespace vlpground::test {

enum class Truth : std::uint8_t { none = 0, ground = 1, obstacle = 2 };

struct Box {  // axis-aligned, in the scene (vehicle) frame
  double x0, x1, y0, y1, z0, z1;
};

struct Scene {
  double ground_z_m = -1.8;
  double grade_start_x_m = 1e9;  // beyond this x the ground rises with `grade`
  double grade = 0.0;
  std::vector<Box> boxes;  // walls are thin boxes
  int columns = 1800;
  // Rotation applied to every ray direction (sensor mounted tilted): pitch about y.
  double sensor_pitch_deg = 0.0;
};

struct SceneFrame {
  Frame frame{2048};
  std::vector<Truth> truth;  // per cell of layer 0
};

double ground_height(const Scene& s, double x);

/// Ray-casts the scene; noise-free.
SceneFrame render(const Scene& scene);

}  // namespace vlpground::test
