// Terrain evaluation and ray casting against terrain and obstacles.
#include "vlpground/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace vlpground::sim {
namespace {

constexpr double kEps = 1e-6;
constexpr double kMinMarchStep_m = 0.05;
constexpr double kMaxMarchStep_m = 4.0;
constexpr double kMarchStepPerMetre = 0.01;
constexpr int kBisectionSteps = 24;

// Intersects [lo, hi] with the interval where lo_b <= origin + t * d <= hi_b.
bool clip_slab(double origin, double d, double lo_b, double hi_b, double& lo, double& hi) {
  if (std::fabs(d) < 1e-12) return origin >= lo_b && origin <= hi_b;
  double t0 = (lo_b - origin) / d;
  double t1 = (hi_b - origin) / d;
  if (t0 > t1) std::swap(t0, t1);
  lo = std::max(lo, t0);
  hi = std::min(hi, t1);
  return lo <= hi;
}

}  // namespace

void Profile::add(double position, double height) {
  if (knots >= kMaxKnots) return;
  at[static_cast<std::size_t>(knots)] = position;
  h[static_cast<std::size_t>(knots)] = height;
  ++knots;
}

double Profile::value(double s) const {
  if (knots == 0) return 0.0;
  if (s <= at[0]) return h[0];
  for (std::size_t i = 1; i < static_cast<std::size_t>(knots); ++i) {
    if (s < at[i]) return h[i - 1] + (h[i] - h[i - 1]) * (s - at[i - 1]) / (at[i] - at[i - 1]);
  }
  return h[static_cast<std::size_t>(knots) - 1];
}

double Profile::max_slope() const {
  double m = 0.0;
  for (std::size_t i = 1; i < static_cast<std::size_t>(knots); ++i)
    m = std::max(m, std::fabs(h[i] - h[i - 1]) / std::max(1e-9, at[i] - at[i - 1]));
  return m;
}

double Terrain::Curve::value(double s) const {
  if (curvature_per_m == 0.0) return 0.0;
  const double u = s - centre_m;
  const double a = std::fabs(u);
  if (a <= cap_m) return 0.5 * curvature_per_m * u * u;
  return curvature_per_m * cap_m * (a - 0.5 * cap_m);
}

double Terrain::height(double x, double y) const {
  double h = 0.0;
  if (road_half_width_m > 0.0) {
    const double ay = std::fabs(y);
    if (ay < road_half_width_m) {
      const double r = ay / road_half_width_m;
      h = crown_m * (1.0 - r * r);
    } else {
      const double off_road = std::min(ay - road_half_width_m, sidewalk_width_m);
      h = curb_height_m + off_road * sidewalk_cross_slope;
    }
  }
  if (grade != 0.0) {
    const double s = x - grade_start_x_m;
    if (s > 0.0) {
      h += s < grade_blend_m ? grade * s * s / (2.0 * grade_blend_m)
                             : grade * (s - 0.5 * grade_blend_m);
    }
  }
  for (const Wave& w : waves) {
    if (w.amplitude_m != 0.0) h += w.amplitude_m * std::sin(w.kx * x + w.ky * y + w.phase);
  }
  h += across.value(y) + curve_x.value(x) + curve_y.value(y);
  if (along.knots > 0 && std::fabs(y) < along_half_width_m) h += along.value(x);
  return h;
}

std::uint8_t Terrain::reflectivity(double /*x*/, double y) const {
  if (road_half_width_m <= 0.0) return 28;  // dirt / grass
  const double ay = std::fabs(y);
  if (ay < road_half_width_m) return 14;                     // asphalt
  if (ay < road_half_width_m + sidewalk_width_m) return 38;  // concrete
  return 26;
}

std::optional<double> intersect_obstacle(const Obstacle& o, const Vec3& origin, const Vec3& dir) {
  double lo = 0.0;
  double hi = std::numeric_limits<double>::infinity();
  if (!clip_slab(origin.z, dir.z, o.z_min_m, o.z_max_m, lo, hi)) return std::nullopt;
  const double px = origin.x - o.cx_m;
  const double py = origin.y - o.cy_m;
  if (o.shape == Shape::box) {
    const double c = std::cos(o.yaw_rad);
    const double s = std::sin(o.yaw_rad);
    const double lx = c * px + s * py;
    const double ly = -s * px + c * py;
    const double dx = c * dir.x + s * dir.y;
    const double dy = -s * dir.x + c * dir.y;
    if (!clip_slab(lx, dx, -o.half_length_m, o.half_length_m, lo, hi)) return std::nullopt;
    if (!clip_slab(ly, dy, -o.half_width_m, o.half_width_m, lo, hi)) return std::nullopt;
  } else {
    const double r = o.half_length_m;
    const double a = dir.x * dir.x + dir.y * dir.y;
    const double b = px * dir.x + py * dir.y;
    const double c = px * px + py * py - r * r;
    if (a < 1e-12) {
      if (c > 0.0) return std::nullopt;
    } else {
      const double disc = b * b - a * c;
      if (disc < 0.0) return std::nullopt;
      const double root = std::sqrt(disc);
      lo = std::max(lo, (-b - root) / a);
      hi = std::min(hi, (-b + root) / a);
      if (lo > hi) return std::nullopt;
    }
  }
  if (lo <= kEps) return std::nullopt;  // behind, or the origin is inside
  return lo;
}

Scene::Scene(SceneKind kind, std::uint64_t seed, Terrain terrain, std::vector<Obstacle> obstacles)
    : kind_(kind), seed_(seed), terrain_(terrain), obstacles_(std::move(obstacles)) {
  for (Obstacle& o : obstacles_) {
    o.bound_radius_m =
        o.shape == Shape::box ? std::hypot(o.half_length_m, o.half_width_m) : o.half_length_m;
  }
}

std::optional<double> Scene::cast_terrain(const Vec3& origin, const Vec3& dir, double max_t) const {
  auto gap_at = [&](double t) {
    return origin.z + t * dir.z - terrain_.height(origin.x + t * dir.x, origin.y + t * dir.y);
  };
  double t = 0.0;
  double gap = gap_at(0.0);
  if (gap <= 0.0) return std::nullopt;  // origin under the terrain
  const double horizontal = std::hypot(dir.x, dir.y);
  // Along the ray the gap shrinks at most this fast (Lipschitz bound of h).
  const double closing_rate = terrain_.max_slope * horizontal - dir.z;
  const double step_margin = terrain_.curb_height_m;  // curbs are steps, not slopes
  while (t < max_t) {
    if (closing_rate <= 0.0 && gap > step_margin) return std::nullopt;  // pulls away
    double step = closing_rate > 0.0 ? (gap - step_margin) / closing_rate : kMaxMarchStep_m;
    // The minimum step grows with distance: terrain features are metres wide, and the
    // bisection below restores full precision once a crossing is bracketed.
    step = std::clamp(step, kMinMarchStep_m + kMarchStepPerMetre * t, kMaxMarchStep_m);
    const double t_next = std::min(t + step, max_t);
    const double gap_next = gap_at(t_next);
    if (gap_next <= 0.0) {
      double a = t;
      double b = t_next;
      for (int i = 0; i < kBisectionSteps; ++i) {
        const double m = 0.5 * (a + b);
        (gap_at(m) > 0.0 ? a : b) = m;
      }
      return 0.5 * (a + b);
    }
    t = t_next;
    gap = gap_next;
  }
  return std::nullopt;
}

std::optional<RayHit> Scene::cast(const Vec3& origin, const Vec3& dir, double max_t,
                                  int skip_object) const {
  std::optional<RayHit> best;
  double limit = max_t;
  const double horizontal = std::hypot(dir.x, dir.y);
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    if (static_cast<int>(i) == skip_object) continue;
    const Obstacle& o = obstacles_[i];
    // Cheap reject on the xy bounding circle.
    const double px = o.cx_m - origin.x;
    const double py = o.cy_m - origin.y;
    const double r = o.bound_radius_m;
    if (horizontal > 1e-9) {
      const double along = (px * dir.x + py * dir.y) / horizontal;
      if (along < -r || along - r > limit * horizontal) continue;
      if (px * px + py * py - along * along > r * r) continue;
    }
    const auto t = intersect_obstacle(o, origin, dir);
    if (t && *t <= limit) {
      limit = *t;
      best = RayHit{*t, static_cast<int>(i)};
    }
  }
  if (const auto t = cast_terrain(origin, dir, limit); t && (!best || *t < best->t_m)) {
    best = RayHit{*t, -1};
  }
  return best;
}

}  // namespace vlpground::sim
