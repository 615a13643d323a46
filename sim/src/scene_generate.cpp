// Procedural, seeded scenes: flat, urban, slope, hills, jam, fences, embankment, bank, bowl,
// crest, garage.
#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include "random.hpp"
#include "vlpground/sim/scene.hpp"

namespace vlpground::sim {
namespace {

using detail::Rng;
constexpr double kPi = 3.14159265358979323846;
// The sensor drives along y = 0 from x = 0; keep this corridor free of obstacles.
constexpr double kCorridorHalfWidth_m = 1.6;
constexpr double kCorridorBack_m = -4.0;
constexpr double kCorridorFront_m = 30.0;

class Builder {
 public:
  Builder(const Terrain& terrain, Rng& rng, double corridor_front_m = kCorridorFront_m)
      : terrain_(terrain), rng_(rng), corridor_front_m_(corridor_front_m) {}

  std::vector<Obstacle> take() { return std::move(obstacles_); }
  // Structures the sensor drives past or under by design (garage walls and ceiling): not
  // checked against the corridor.
  void structure(const Obstacle& o) { obstacles_.push_back(o); }
  [[nodiscard]] std::size_t count() const { return obstacles_.size(); }

  // Boxes stand on the terrain: sunk to the lowest footprint point, top above the centre.
  bool box(double cx, double cy, double length, double width, double yaw, double height,
           std::uint8_t refl, float transparency = 0.f, double lift = 0.0) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    double base = terrain_.height(cx, cy);
    for (int i = 0; i < 4; ++i) {
      const double lx = (i & 1 ? 0.5 : -0.5) * length;
      const double ly = (i & 2 ? 0.5 : -0.5) * width;
      base = std::min(base, terrain_.height(cx + c * lx - s * ly, cy + s * lx + c * ly));
    }
    Obstacle o;
    o.shape = Shape::box;
    o.cx_m = cx;
    o.cy_m = cy;
    o.half_length_m = 0.5 * length;
    o.half_width_m = 0.5 * width;
    o.yaw_rad = yaw;
    o.z_min_m = lift > 0.0 ? terrain_.height(cx, cy) + lift : base - 0.1;
    o.z_max_m = terrain_.height(cx, cy) + height;
    o.reflectivity = refl;
    o.transparency = transparency;
    return add(o);
  }

  bool cylinder(double cx, double cy, double radius, double z_lo, double z_hi, std::uint8_t refl,
                float transparency = 0.f) {
    Obstacle o;
    o.shape = Shape::cylinder;
    o.cx_m = cx;
    o.cy_m = cy;
    o.half_length_m = radius;
    const double ground = terrain_.height(cx, cy);
    o.z_min_m = z_lo > 0.0 ? ground + z_lo : ground - 0.1 - radius * terrain_.max_slope;
    o.z_max_m = ground + z_hi;
    o.reflectivity = refl;
    o.transparency = transparency;
    return add(o);
  }

  void car(double cx, double cy, double yaw) {
    box(cx, cy, rng_.uniform(4.0, 4.9), rng_.uniform(1.7, 1.95), yaw, rng_.uniform(1.35, 1.65),
        static_cast<std::uint8_t>(rng_.integer(20, 110)));
  }
  void truck(double cx, double cy, double yaw) {
    box(cx, cy, rng_.uniform(7.0, 11.0), 2.45, yaw, rng_.uniform(2.8, 3.6),
        static_cast<std::uint8_t>(rng_.integer(30, 90)));
  }
  void pedestrian(double cx, double cy) {
    cylinder(cx, cy, rng_.uniform(0.2, 0.3), 0.0, rng_.uniform(1.55, 1.95),
             static_cast<std::uint8_t>(rng_.integer(20, 60)));
  }
  void pole(double cx, double cy) {
    cylinder(cx, cy, rng_.uniform(0.07, 0.15), 0.0, rng_.uniform(3.5, 8.0),
             static_cast<std::uint8_t>(rng_.integer(50, 120)));
  }
  void tree(double cx, double cy) {
    const double trunk = rng_.uniform(1.8, 3.0);
    if (!cylinder(cx, cy, rng_.uniform(0.12, 0.3), 0.0, trunk + 0.3, 45)) return;
    cylinder(cx, cy, rng_.uniform(1.4, 3.0), trunk, trunk + rng_.uniform(2.5, 5.0), 40, 0.55f);
  }
  void facade(double cx, double cy, double length, double yaw) {
    box(cx, cy, length, rng_.uniform(0.6, 1.2), yaw, rng_.uniform(6.0, 16.0),
        static_cast<std::uint8_t>(rng_.integer(40, 90)));
  }
  void fence(double cx, double cy, double length, double yaw, bool mesh) {
    box(cx, cy, length, rng_.uniform(0.05, 0.12), yaw, rng_.uniform(0.5, 1.3),
        static_cast<std::uint8_t>(rng_.integer(30, 100)), mesh ? 0.5f : 0.f);
  }
  void barrier(double cx, double cy, double length, double yaw) {
    box(cx, cy, length, 0.6, yaw, rng_.uniform(0.7, 0.9), 70);
  }

 private:
  bool add(const Obstacle& o) {
    const double r = std::hypot(o.half_length_m, o.half_width_m);
    if (std::fabs(o.cy_m) - r < kCorridorHalfWidth_m && o.cx_m + r > kCorridorBack_m &&
        o.cx_m - r < corridor_front_m_) {
      return false;
    }
    obstacles_.push_back(o);
    return true;
  }

  const Terrain& terrain_;
  Rng& rng_;
  double corridor_front_m_;
  std::vector<Obstacle> obstacles_;
};

double side(Rng& rng) { return rng.chance(0.5) ? 1.0 : -1.0; }

// Trees, bushes, rocks and sheds scattered over open country (hills, bowl, embankment fields).
void countryside(Builder& b, Rng& rng, int count) {
  for (int i = 0; i < count; ++i) {
    const double x = rng.uniform(-60.0, 80.0);
    const double y = rng.uniform(-60.0, 60.0);
    const double kind = rng.uniform();
    if (kind < 0.45)
      b.tree(x, y);
    else if (kind < 0.75)
      b.cylinder(x, y, rng.uniform(0.4, 1.4), 0.0, rng.uniform(0.4, 1.4), 35, 0.35f);
    else
      b.box(x, y, rng.uniform(0.5, 2.0), rng.uniform(0.5, 1.5), rng.uniform(0.0, kPi),
            rng.uniform(0.3, 1.2), 50);
  }
}

// Cars on a two-way road of half width `road` (none in the sensor's own corridor).
void traffic(Builder& b, Rng& rng, double road, int count) {
  for (int i = 0; i < count; ++i) {
    const double lane = side(rng) * std::max(0.0, road - 1.9);
    b.car(rng.uniform(-50.0, 70.0), lane + rng.uniform(-0.3, 0.3), rng.uniform(-0.03, 0.03));
  }
}

// Parked cars, facades, poles, trees and people along a street of half width `road`.
void street(Builder& b, Rng& rng, double road, double walk) {
  for (double x = -60.0; x < 90.0; x += rng.uniform(5.5, 14.0)) {
    if (rng.chance(0.65)) b.car(x, side(rng) * (road - 1.1), rng.uniform(-0.05, 0.05));
  }
  for (double s : {-1.0, 1.0}) {
    for (double x = -70.0; x < 100.0;) {
      const double len = rng.uniform(10.0, 30.0);
      if (rng.chance(0.8))
        b.facade(x + 0.5 * len, s * (road + walk + rng.uniform(0.8, 6.0)), len, 0.0);
      x += len + rng.uniform(0.0, 8.0);
    }
    for (double x = -50.0; x < 80.0; x += rng.uniform(8.0, 20.0)) {
      const double y = s * (road + rng.uniform(0.3, std::max(0.4, walk - 0.3)));
      if (rng.chance(0.5))
        b.pole(x, y);
      else if (rng.chance(0.5))
        b.tree(x, y);
      else
        b.pedestrian(x, y);
    }
  }
}

Terrain road_terrain(double half_width) {
  Terrain t;
  t.road_half_width_m = half_width;
  t.max_slope = 0.02;
  return t;
}

Scene make_flat(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(4.0, 6.5));
  terrain.sidewalk_width_m = rng.uniform(2.0, 4.0);
  Builder b(terrain, rng);
  street(b, rng, terrain.road_half_width_m, terrain.sidewalk_width_m);
  for (int i = 0; i < 4; ++i) b.car(rng.uniform(-40.0, 60.0), rng.uniform(-2.5, 2.5), 0.0);
  return Scene(SceneKind::flat, seed, terrain, b.take());
}

Scene make_urban(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(3.5, 6.0));
  terrain.crown_m = rng.uniform(0.06, 0.12);
  terrain.curb_height_m = rng.uniform(0.10, 0.18);
  terrain.sidewalk_width_m = rng.uniform(2.0, 4.5);
  terrain.sidewalk_cross_slope = 0.02;
  terrain.max_slope = 2.0 * terrain.crown_m / terrain.road_half_width_m + 0.03;
  Builder b(terrain, rng);
  street(b, rng, terrain.road_half_width_m, terrain.sidewalk_width_m);
  for (int i = 0; i < 6; ++i) {
    b.pedestrian(rng.uniform(-30.0, 50.0),
                 side(rng) * (terrain.road_half_width_m + rng.uniform(0.5, 2.0)));
  }
  return Scene(SceneKind::urban, seed, terrain, b.take());
}

Scene make_slope(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(4.0, 6.0));
  terrain.sidewalk_width_m = 3.0;
  terrain.grade_start_x_m = rng.uniform(12.0, 25.0);
  terrain.grade = side(rng) * rng.uniform(0.06, 0.14);  // hill (+) or ramp down (-)
  terrain.grade_blend_m = rng.uniform(4.0, 10.0);
  terrain.max_slope = std::fabs(terrain.grade) + 0.03;
  Builder b(terrain, rng);
  for (double x = -40.0; x < 90.0; x += rng.uniform(6.0, 16.0)) {
    const double y = side(rng) * (terrain.road_half_width_m + rng.uniform(1.0, 8.0));
    if (rng.chance(0.4))
      b.tree(x, y);
    else if (rng.chance(0.5))
      b.pole(x, y);
    else
      b.car(x, side(rng) * (terrain.road_half_width_m - 1.1), 0.0);
  }
  for (int i = 0; i < 3; ++i) b.car(rng.uniform(30.0, 70.0), rng.uniform(-3.0, 3.0), 0.0);
  return Scene(SceneKind::slope, seed, terrain, b.take());
}

Scene make_hills(std::uint64_t seed, Rng& rng) {
  Terrain terrain;
  double slope = 0.0;
  for (Terrain::Wave& w : terrain.waves) {
    const double wavelength = rng.uniform(18.0, 60.0);
    const double heading = rng.uniform(0.0, 2.0 * kPi);
    const double k = 2.0 * kPi / wavelength;
    w = {rng.uniform(0.15, 0.9) * wavelength / 40.0, k * std::cos(heading), k * std::sin(heading),
         rng.uniform(0.0, 2.0 * kPi)};
    slope += w.amplitude_m * k;
  }
  terrain.max_slope = slope + 0.01;
  Builder b(terrain, rng);
  countryside(b, rng, 70);
  return Scene(SceneKind::hills, seed, terrain, b.take());
}

Scene make_jam(std::uint64_t seed, Rng& rng) {
  const int lanes_left = rng.integer(1, 2);
  const int lanes_right = rng.integer(1, 2);
  Terrain terrain = road_terrain(3.5 * (std::max(lanes_left, lanes_right) + 0.5) + 1.0);
  terrain.sidewalk_width_m = 2.5;
  // The sensor barely moves in a jam: the corridor ends 3 m ahead (see kJamSpeedMax).
  Builder b(terrain, rng, 3.0);
  for (int lane = -lanes_right; lane <= lanes_left; ++lane) {
    for (double x = rng.uniform(-55.0, -45.0); x < 80.0; x += rng.uniform(5.6, 8.0)) {
      const double y = 3.5 * lane + rng.uniform(-0.3, 0.3);
      if (lane == 0 && std::fabs(x) < 9.5) continue;
      if (rng.chance(0.15))
        b.truck(x, y, rng.uniform(-0.03, 0.03));
      else
        b.car(x, y, rng.uniform(-0.05, 0.05));
    }
  }
  // Own lane: bumper to bumper just ahead and just behind.
  b.car(rng.uniform(6.5, 8.0), 0.0, 0.0);
  b.car(rng.uniform(-8.5, -7.0), 0.0, 0.0);
  for (double s : {-1.0, 1.0}) {
    for (double x = -60.0; x < 90.0; x += 20.0) {
      b.facade(x, s * (terrain.road_half_width_m + 3.5), rng.uniform(12.0, 19.0), 0.0);
    }
  }
  return Scene(SceneKind::jam, seed, terrain, b.take());
}

Scene make_fences(std::uint64_t seed, Rng& rng) {
  Terrain terrain;
  terrain.waves[0] = {0.15, 0.08, 0.03, rng.uniform(0.0, 2.0 * kPi)};
  terrain.max_slope = 0.03;
  Builder b(terrain, rng);
  for (int i = 0; i < 26; ++i) {
    const double r = rng.uniform(4.0, 25.0);
    const double a = rng.uniform(0.0, 2.0 * kPi);
    const double yaw = rng.uniform(0.0, kPi);
    if (rng.chance(0.3))
      b.barrier(r * std::cos(a), r * std::sin(a), rng.uniform(2.0, 8.0), yaw);
    else
      b.fence(r * std::cos(a), r * std::sin(a), rng.uniform(4.0, 16.0), yaw, rng.chance(0.4));
  }
  // Far obstacles at 28..45 m.
  for (int i = 0; i < 40; ++i) {
    const double r = rng.uniform(28.0, 45.0);
    const double a = rng.uniform(0.0, 2.0 * kPi);
    const double x = r * std::cos(a), y = r * std::sin(a);
    const double kind = rng.uniform();
    if (kind < 0.3)
      b.car(x, y, rng.uniform(0.0, kPi));
    else if (kind < 0.5)
      b.facade(x, y, rng.uniform(6.0, 15.0), a + 0.5 * kPi);
    else if (kind < 0.7)
      b.tree(x, y);
    else if (kind < 0.85)
      b.pedestrian(x, y);
    else
      b.pole(x, y);
  }
  return Scene(SceneKind::fences, seed, terrain, b.take());
}

// A road on a levee: crowned road, shoulders, side slopes 1:3..1:4 down to fields 1.5-3 m
// lower on both sides.
Scene make_embankment(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(3.5, 6.0));
  terrain.crown_m = rng.uniform(0.03, 0.08);
  const double shoulder = terrain.road_half_width_m + rng.uniform(1.0, 2.5);
  const double run = rng.uniform(3.0, 4.0);
  const double drop_right = rng.uniform(1.5, 3.0), drop_left = rng.uniform(1.5, 3.0);
  terrain.across.add(-shoulder - drop_right * run, -drop_right);
  terrain.across.add(-shoulder, 0.0);
  terrain.across.add(shoulder, 0.0);
  terrain.across.add(shoulder + drop_left * run, -drop_left);
  terrain.max_slope = terrain.across.max_slope() + 0.03;
  Builder b(terrain, rng);
  traffic(b, rng, terrain.road_half_width_m, 5);
  for (double x = -50.0; x < 80.0; x += rng.uniform(8.0, 25.0))  // posts on the shoulders
    b.pole(x, side(rng) * (shoulder - 0.3));
  countryside(b, rng, 60);
  return Scene(SceneKind::embankment, seed, terrain, b.take());
}

// A road along a cut slope (1:2..1:3) rising 2-5 m on one side behind a ditch; the other
// side falls gently away.
Scene make_bank(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(3.0, 5.0));
  terrain.crown_m = rng.uniform(0.03, 0.08);
  const double w = terrain.road_half_width_m;
  const double s = side(rng);
  const double toe = w + rng.uniform(1.2, 2.0);
  const double bank_height = rng.uniform(2.0, 5.0);
  const double top = toe + bank_height * rng.uniform(2.0, 3.0);
  std::array<std::array<double, 2>, 6> knots = {{{-s * (w + 8.0), -0.4},
                                                 {-s * w, 0.0},
                                                 {s * w, 0.0},
                                                 {s * (w + 0.6), -0.3},  // ditch
                                                 {s * toe, -0.3},
                                                 {s * top, bank_height}}};
  std::sort(knots.begin(), knots.end());
  for (const auto& k : knots) terrain.across.add(k[0], k[1]);
  terrain.max_slope = terrain.across.max_slope() + 0.03;
  Builder b(terrain, rng);
  traffic(b, rng, w, 5);
  for (double x = -50.0; x < 80.0; x += rng.uniform(5.0, 15.0)) {
    const double y = s * (top + rng.uniform(0.0, 20.0));  // trees and sheds on the top
    if (rng.chance(0.6))
      b.tree(x, y);
    else
      b.box(x, y, rng.uniform(2.0, 6.0), rng.uniform(2.0, 5.0), 0.0, rng.uniform(2.0, 4.0), 60);
  }
  for (double x = -50.0; x < 80.0; x += rng.uniform(10.0, 25.0))  // posts on the far side
    b.pole(x, -s * (w + rng.uniform(0.5, 3.0)));
  for (int i = 0; i < 8; ++i)  // bushes on the bank face
    b.cylinder(rng.uniform(-40.0, 60.0), s * rng.uniform(toe + 0.5, top), rng.uniform(0.4, 1.0),
               0.0, rng.uniform(0.5, 1.3), 35, 0.35f);
  return Scene(SceneKind::bank, seed, terrain, b.take());
}

// A round bowl or a valley around the sensor: the ground rises 1.5-4 m within 40 m.
Scene make_bowl(std::uint64_t seed, Rng& rng) {
  Terrain terrain;
  const double k = rng.uniform(0.002, 0.005);
  const double cap = 50.0;
  if (rng.chance(0.5)) {  // round bowl, its bottom near the sensor
    terrain.curve_x = {rng.uniform(-10.0, 15.0), k, cap};
    terrain.curve_y = {rng.uniform(-8.0, 8.0), k, cap};
  } else {  // valley along the drive, a gentle sag along it
    terrain.curve_y = {rng.uniform(-4.0, 4.0), 1.5 * k, cap};
    terrain.curve_x = {rng.uniform(-20.0, 20.0), rng.uniform(-0.001, 0.001), cap};
  }
  terrain.max_slope = std::fabs(terrain.curve_x.curvature_per_m) * cap +
                      std::fabs(terrain.curve_y.curvature_per_m) * cap + 0.01;
  Builder b(terrain, rng);
  countryside(b, rng, 60);
  for (int i = 0; i < 4; ++i)
    b.car(rng.uniform(-30.0, 50.0), side(rng) * rng.uniform(3.0, 20.0), 0.0);
  return Scene(SceneKind::bowl, seed, terrain, b.take());
}

// A crowned road over a crest: a vertical curve with grades up to 8-12 % either side, verges
// falling away from the road.
Scene make_crest(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(3.5, 5.5));
  terrain.crown_m = rng.uniform(0.06, 0.12);
  terrain.sidewalk_width_m = 8.0;
  terrain.sidewalk_cross_slope = -0.03;
  const double k = rng.uniform(0.002, 0.005);
  terrain.curve_x = {rng.uniform(-5.0, 20.0), -k, rng.uniform(0.08, 0.12) / k};
  terrain.max_slope = 2.0 * terrain.crown_m / terrain.road_half_width_m + 0.12 + 0.04;
  Builder b(terrain, rng);
  traffic(b, rng, terrain.road_half_width_m, 6);
  for (double x = -50.0; x < 80.0; x += rng.uniform(6.0, 16.0)) {
    const double y = side(rng) * (terrain.road_half_width_m + rng.uniform(1.0, 12.0));
    if (rng.chance(0.5))
      b.tree(x, y);
    else
      b.pole(x, y);
  }
  return Scene(SceneKind::crest, seed, terrain, b.take());
}

// A ramp (10-16 %) between retaining walls down into an underground garage 2.8-3.5 m deep,
// under a building; a street with parked cars and facades around it at the upper level.
Scene make_garage(std::uint64_t seed, Rng& rng) {
  Terrain terrain = road_terrain(rng.uniform(3.0, 4.0));
  const double wall = 0.3;
  const double inner = terrain.road_half_width_m;
  terrain.along_half_width_m = inner + wall;
  const double x0 = rng.uniform(-6.0, 8.0);
  const double grade = rng.uniform(0.10, 0.16);
  const double depth = rng.uniform(2.8, 3.5);
  constexpr double kTransition = 3.0;  // half-grade transitions at both ends of the ramp
  const double x1 = x0 + depth / grade + kTransition;
  terrain.along.add(x0, 0.0);
  terrain.along.add(x0 + kTransition, -0.5 * grade * kTransition);
  terrain.along.add(x1 - kTransition, -depth + 0.5 * grade * kTransition);
  terrain.along.add(x1, -depth);
  terrain.max_slope = grade + 0.02;
  constexpr double kGarageLength = 40.0;
  Builder b(terrain, rng);
  Obstacle o;
  o.reflectivity = 70;
  for (double s : {-1.0, 1.0}) {  // retaining walls, 1 m parapet above the street
    o.cx_m = 0.5 * (x0 + x1 + kGarageLength);
    o.cy_m = s * (inner + 0.5 * wall);
    o.half_length_m = 0.5 * (x1 + kGarageLength - x0);
    o.half_width_m = 0.5 * wall;
    o.z_min_m = -depth - 0.1;
    o.z_max_m = 1.0;
    b.structure(o);
  }
  o.reflectivity = 55;  // the building over the garage: its ceiling 2.5 m above the floor
  o.cx_m = x1 + 0.5 * kGarageLength;
  o.cy_m = 0.0;
  o.half_length_m = 0.5 * kGarageLength;
  o.half_width_m = inner + wall + 10.0;
  o.z_min_m = -depth + 2.5;
  o.z_max_m = rng.uniform(8.0, 15.0);
  b.structure(o);
  o.cx_m = x1 + kGarageLength;  // the garage's back wall
  o.half_length_m = 0.3;
  o.half_width_m = inner + wall;
  o.z_min_m = -depth - 0.1;
  b.structure(o);
  for (double x = -60.0; x < x0 - 3.0; x += rng.uniform(6.0, 12.0))  // street before the ramp
    if (rng.chance(0.6)) b.car(x, side(rng) * (inner + 2.5), 0.0);
  for (double s : {-1.0, 1.0}) {
    for (double x = x0; x < x1 + 5.0; x += rng.uniform(6.0, 12.0)) {
      const double y = s * (inner + wall + rng.uniform(1.5, 8.0));
      if (rng.chance(0.4))
        b.car(x, y, 0.0);
      else if (rng.chance(0.5))
        b.pole(x, y);
      else
        b.pedestrian(x, y);
    }
    for (double x = -70.0; x < x0 - 2.0;) {  // facades along the street before the ramp
      const double len = rng.uniform(10.0, 25.0);
      b.facade(x + 0.5 * len, s * (inner + rng.uniform(8.0, 14.0)), len, 0.0);
      x += len + rng.uniform(2.0, 8.0);
    }
  }
  return Scene(SceneKind::garage, seed, terrain, b.take());
}

constexpr std::array<std::string_view, 11> kNames = {"flat", "urban",  "slope",      "hills",
                                                     "jam",  "fences", "embankment", "bank",
                                                     "bowl", "crest",  "garage"};

}  // namespace

std::optional<SceneKind> parse_scene_kind(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) return static_cast<SceneKind>(i);
  }
  return std::nullopt;
}

std::string_view to_string(SceneKind kind) { return kNames[static_cast<std::size_t>(kind)]; }

std::string_view scene_kind_list() {
  return "flat|urban|slope|hills|jam|fences|embankment|bank|bowl|crest|garage";
}

Scene Scene::generate(SceneKind kind, std::uint64_t seed) {
  Rng rng(seed, 0x5CE0E000u + static_cast<std::uint64_t>(kind));
  switch (kind) {
    case SceneKind::flat:
      return make_flat(seed, rng);
    case SceneKind::urban:
      return make_urban(seed, rng);
    case SceneKind::slope:
      return make_slope(seed, rng);
    case SceneKind::hills:
      return make_hills(seed, rng);
    case SceneKind::jam:
      return make_jam(seed, rng);
    case SceneKind::fences:
      return make_fences(seed, rng);
    case SceneKind::embankment:
      return make_embankment(seed, rng);
    case SceneKind::bank:
      return make_bank(seed, rng);
    case SceneKind::bowl:
      return make_bowl(seed, rng);
    case SceneKind::crest:
      return make_crest(seed, rng);
    case SceneKind::garage:
      return make_garage(seed, rng);
  }
  return make_flat(seed, rng);
}

}  // namespace vlpground::sim
