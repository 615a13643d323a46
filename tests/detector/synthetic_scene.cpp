#include "synthetic_scene.hpp"

#include <algorithm>
#include <limits>

namespace vlpground::test {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::optional<double> hit_ground(const Scene& s, const double d[3]) {
  std::optional<double> best;
  if (d[2] < 0) {  // flat part
    const double t = s.ground_z_m / d[2];
    if (t * d[0] < s.grade_start_x_m) best = t;
  }
  const double denom = d[2] - s.grade * d[0];  // rising part z = z0 + g (x - xs)
  if (std::abs(denom) > 1e-12) {
    const double t = (s.ground_z_m - s.grade * s.grade_start_x_m) / denom;
    if (t > 0 && t * d[0] >= s.grade_start_x_m && (!best || t < *best)) best = t;
  }
  return best;
}

std::optional<double> hit_box(const Box& b, const double d[3]) {
  double t0 = 0, t1 = std::numeric_limits<double>::max();
  const double lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1, b.y1, b.z1};
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (0 < lo[k] || 0 > hi[k]) return std::nullopt;
      continue;
    }
    double a = lo[k] / d[k], c = hi[k] / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  if (t0 > t1 || t0 <= 0) return std::nullopt;
  return t0;
}

}  // namespace

double ground_height(const Scene& s, double x) {
  return x < s.grade_start_x_m ? s.ground_z_m : s.ground_z_m + s.grade * (x - s.grade_start_x_m);
}

SceneFrame render(const Scene& scene) {
  SceneFrame out;
  out.truth.assign(static_cast<std::size_t>(kLasers * out.frame.stride()), Truth::none);
  const double pitch = scene.sensor_pitch_deg * kPi / 180;
  for (int c = 0; c < scene.columns; ++c) {
    const int col = out.frame.append_column();
    const double az = 2 * kPi * c / scene.columns;
    for (int ring = 0; ring < kLasers; ++ring) {
      const double el = (-15.0 + 2.0 * ring) * kPi / 180;
      const double s[3] = {std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az),
                           std::sin(el)};  // sensor frame
      // Scene direction: rotate the sensor ray by the mounting pitch (about y).
      const double d[3] = {std::cos(pitch) * s[0] + std::sin(pitch) * s[2], s[1],
                           -std::sin(pitch) * s[0] + std::cos(pitch) * s[2]};
      std::optional<double> t = hit_ground(scene, d);
      Truth truth = Truth::ground;
      for (const Box& b : scene.boxes) {
        const auto tb = hit_box(b, d);
        if (tb && (!t || *tb < *t)) {
          t = tb;
          truth = Truth::obstacle;
        }
      }
      if (!t || *t > 120) continue;
      const std::size_t i = out.frame.index(ring, col);
      ReturnLayer& l = out.frame.layer[0];
      l.range_m[i] = static_cast<float>(*t);
      l.x_m[i] = static_cast<float>(*t * s[0]);
      l.y_m[i] = static_cast<float>(*t * s[1]);
      l.z_m[i] = static_cast<float>(*t * s[2]);
      l.valid[i] = 1;
      out.truth[i] = truth;
    }
  }
  return out;
}

}  // namespace vlpground::test
