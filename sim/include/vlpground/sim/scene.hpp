// Procedural scenes for the simulator: a terrain height field z = h(x, y) plus boxes and
// vertical cylinders (cars, facades, poles, people, tree trunks and canopies, fences).
// World frame: x forward along the road (the sensor drives along +x from x = 0), y left, z up.
//
// Thread-safety: a built Scene is immutable; ray casting is const and may run concurrently.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace vlpground::sim {

enum class SceneKind : std::uint8_t {
  flat,
  urban,
  slope,
  hills,
  jam,
  fences,
  embankment,  // road on a levee, fields 1.5-3 m lower on both sides
  bank,        // road along a side bank (cut slope rising beside it)
  bowl,        // valley or round bowl around the sensor
  crest,       // crowned road over a crest (vertical curve)
  garage,      // ramp down into an underground garage
};

std::optional<SceneKind> parse_scene_kind(std::string_view name);
std::string_view to_string(SceneKind kind);
/// "flat|urban|slope|hills|jam|fences|embankment|bank|bowl|crest|garage"
std::string_view scene_kind_list();

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

/// Piecewise-linear height profile over one coordinate: knots (at[i], h[i]) with at
/// increasing, constant beyond the first and last knot. No knots: 0 everywhere.
struct Profile {
  static constexpr int kMaxKnots = 10;
  std::array<double, kMaxKnots> at{}, h{};
  int knots = 0;
  void add(double position, double height);  // appends a knot (positions increasing)
  [[nodiscard]] double value(double s) const;
  [[nodiscard]] double max_slope() const;  // largest |dh/ds| between knots
};

/// Analytic terrain: flat plane, optional crowned road with curbs and sidewalks, optional
/// grade change ahead, optional rolling hills (sum of sinusoids), optional cross and
/// longitudinal profiles (embankment, bank, garage ramp) and vertical curves (bowl, crest).
struct Terrain {
  // Crowned road with curbs (urban): |y| < road_half_width_m is road, crown drops the edges.
  double road_half_width_m = 0.0;  // 0: no road profile
  double crown_m = 0.0;            // road centre is this much higher than its edges
  double curb_height_m = 0.0;      // step up from the road edge to the sidewalk
  double sidewalk_width_m = 0.0;
  double sidewalk_cross_slope = 0.0;  // rises away from the road
  // Grade change (slope): h grows by grade * (x - start) beyond start, blended over blend_m.
  double grade_start_x_m = 0.0;
  double grade = 0.0;  // signed rise per metre (0.06 .. 0.14, negative for a dip)
  double grade_blend_m = 0.0;
  // Rolling hills: sum of a_i * sin(kx_i x + ky_i y + phase_i).
  struct Wave {
    double amplitude_m = 0.0, kx = 0.0, ky = 0.0, phase = 0.0;
  };
  std::array<Wave, 4> waves{};
  // Cross-section: h += across.value(y) (embankment, side bank).
  Profile across;
  // Longitudinal profile: h += along.value(x) where |y| < along_half_width_m (a ramp cut
  // into the ground between retaining walls), else nothing.
  Profile along;
  double along_half_width_m = 0.0;
  // Vertical curves: h += c/2 * s^2 for |s| <= cap_m, continued linearly beyond (s = x - x0
  // with curve_x, s = y - y0 with curve_y). c > 0: sag (bowl, valley), c < 0: crest.
  struct Curve {
    double centre_m = 0.0, curvature_per_m = 0.0, cap_m = 0.0;
    [[nodiscard]] double value(double s) const;
  };
  Curve curve_x, curve_y;
  /// Upper bound of |grad h| away from curbs (used for safe ray-march steps).
  double max_slope = 0.05;

  [[nodiscard]] double height(double x, double y) const;
  /// Base reflectivity (0..255) of the surface material at (x, y).
  [[nodiscard]] std::uint8_t reflectivity(double x, double y) const;
};

enum class Shape : std::uint8_t { box, cylinder };

struct Obstacle {
  Shape shape = Shape::box;
  double cx_m = 0.0, cy_m = 0.0;
  double half_length_m = 0.5;  // box: along its yawed x axis; cylinder: radius
  double half_width_m = 0.5;   // box only
  double yaw_rad = 0.0;        // box only
  double z_min_m = 0.0, z_max_m = 1.0;
  std::uint8_t reflectivity = 60;
  // 0: opaque. > 0: semi-transparent (tree canopy, mesh fence): a ray hitting it is fully
  // blocked with probability 1 - transparency; otherwise it leaves a weak partial echo with
  // probability 0.6 and travels on to the surface behind.
  float transparency = 0.f;
  // Precomputed bounding circle in xy.
  double bound_radius_m = 0.0;
};

/// Nearest surface along a ray.
struct RayHit {
  double t_m = 0.0;  // distance along the (unit) ray
  int object = -1;   // obstacle index, or -1 for terrain
};

class Scene {
 public:
  Scene(SceneKind kind, std::uint64_t seed, Terrain terrain, std::vector<Obstacle> obstacles);

  /// Builds the procedural scene `kind` from `seed` (deterministic).
  static Scene generate(SceneKind kind, std::uint64_t seed);

  /// Nearest hit of the ray origin + t * dir (dir unit length) with t in (0, max_t],
  /// ignoring obstacle `skip_object` (-1: none). nullopt: nothing within max_t.
  [[nodiscard]] std::optional<RayHit> cast(const Vec3& origin, const Vec3& dir, double max_t,
                                           int skip_object = -1) const;

  /// Terrain-only intersection (ray-march + bisection refinement).
  [[nodiscard]] std::optional<double> cast_terrain(const Vec3& origin, const Vec3& dir,
                                                   double max_t) const;

  [[nodiscard]] SceneKind kind() const { return kind_; }
  [[nodiscard]] std::uint64_t seed() const { return seed_; }
  [[nodiscard]] const Terrain& terrain() const { return terrain_; }
  [[nodiscard]] const std::vector<Obstacle>& obstacles() const { return obstacles_; }

 private:
  SceneKind kind_;
  std::uint64_t seed_;
  Terrain terrain_;
  std::vector<Obstacle> obstacles_;
};

/// Distance along the ray to `o` (entry point), or nullopt. dir must be unit length.
std::optional<double> intersect_obstacle(const Obstacle& o, const Vec3& origin, const Vec3& dir);

}  // namespace vlpground::sim
