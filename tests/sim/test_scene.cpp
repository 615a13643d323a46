// Ray casting against terrain and obstacles, and procedural scene determinism.
#include <catch2/catch.hpp>
#include <cmath>

#include "vlpground/sim/scene.hpp"

using namespace vlpground::sim;

namespace {
constexpr double kPi = 3.14159265358979323846;
Vec3 unit(double x, double y, double z) {
  const double n = std::sqrt(x * x + y * y + z * z);
  return {x / n, y / n, z / n};
}
}  // namespace

TEST_CASE("terrain ray-march finds the plane and the grade", "[sim][scene]") {
  Terrain flat;
  const Scene scene(SceneKind::flat, 1, flat, {});
  const double e = 15.0 * kPi / 180.0;
  const auto t = scene.cast_terrain({0, 0, 2.0}, {std::cos(e), 0, -std::sin(e)}, 100.0);
  REQUIRE(t);
  CHECK(*t == Approx(2.0 / std::sin(e)).margin(1e-4));
  CHECK_FALSE(scene.cast_terrain({0, 0, 2.0}, {1, 0, 0}, 100.0));
  CHECK_FALSE(scene.cast_terrain({0, 0, 2.0}, unit(1, 0, -0.01), 100.0));  // beyond 100 m

  Terrain ramp;
  ramp.grade = 0.1;
  ramp.grade_start_x_m = 10.0;
  ramp.max_slope = 0.12;
  const Scene hill(SceneKind::slope, 1, ramp, {});
  const Vec3 dir = unit(1, 0, -0.05);
  const auto th = hill.cast_terrain({0, 0, 1.0}, dir, 100.0);
  REQUIRE(th);
  // 1 - 0.05 x = 0.1 (x - 10)  =>  x = 2 / 0.15
  CHECK(*th * dir.x == Approx(2.0 / 0.15).margin(1e-3));
}

TEST_CASE("curb step is found as terrain", "[sim][scene]") {
  Terrain street;
  street.road_half_width_m = 4.0;
  street.curb_height_m = 0.15;
  street.sidewalk_width_m = 3.0;
  const Scene scene(SceneKind::urban, 1, street, {});
  // Grazing ray just above the road towards the left curb: hits the curb face at y = 4.
  const auto t = scene.cast_terrain({0, 0, 0.1}, {0, 1, 0}, 50.0);
  REQUIRE(t);
  CHECK(*t == Approx(4.0).margin(1e-3));
  CHECK(street.height(0, 5.0) == Approx(0.15));
}

TEST_CASE("boxes and cylinders are hit at their surfaces", "[sim][scene]") {
  Obstacle box;
  box.cx_m = 10.0;
  box.half_length_m = 1.0;
  box.half_width_m = 2.0;
  box.z_min_m = -0.1;
  box.z_max_m = 1.5;
  auto t = intersect_obstacle(box, {0, 0, 1.0}, {1, 0, 0});
  REQUIRE(t);
  CHECK(*t == Approx(9.0));
  CHECK_FALSE(intersect_obstacle(box, {0, 0, 2.0}, {1, 0, 0}));  // over it
  box.yaw_rad = kPi / 2;                                         // now 4 m long in x
  t = intersect_obstacle(box, {0, 0, 1.0}, {1, 0, 0});
  REQUIRE(t);
  CHECK(*t == Approx(8.0));

  Obstacle pole;
  pole.shape = Shape::cylinder;
  pole.cx_m = 0.0;
  pole.cy_m = 5.0;
  pole.half_length_m = 0.5;
  pole.z_min_m = 0.0;
  pole.z_max_m = 3.0;
  t = intersect_obstacle(pole, {0, 0, 1.0}, {0, 1, 0});
  REQUIRE(t);
  CHECK(*t == Approx(4.5));
  // From above, through the top cap.
  t = intersect_obstacle(pole, {0, 5.0, 10.0}, {0, 0, -1});
  REQUIRE(t);
  CHECK(*t == Approx(7.0));

  const Scene scene(SceneKind::flat, 1, Terrain{}, {box, pole});
  const auto hit = scene.cast({0, 0, 1.0}, {1, 0, 0}, 100.0);
  REQUIRE(hit);
  CHECK(hit->object == 0);
  const auto skipped = scene.cast({0, 0, 1.0}, {1, 0, 0}, 100.0, 0);
  CHECK_FALSE(skipped);
}

TEST_CASE("scenes are deterministic per seed and differ across seeds", "[sim][scene]") {
  for (const char* name : {"flat", "urban", "slope", "hills", "jam", "fences", "embankment", "bank",
                           "bowl", "crest", "garage"}) {
    const auto kind = parse_scene_kind(name);
    REQUIRE(kind);
    CHECK(to_string(*kind) == name);
    const Scene a = Scene::generate(*kind, 7);
    const Scene b = Scene::generate(*kind, 7);
    const Scene c = Scene::generate(*kind, 8);
    REQUIRE(a.obstacles().size() == b.obstacles().size());
    REQUIRE_FALSE(a.obstacles().empty());
    for (std::size_t i = 0; i < a.obstacles().size(); ++i) {
      CHECK(a.obstacles()[i].cx_m == b.obstacles()[i].cx_m);
      CHECK(a.obstacles()[i].z_max_m == b.obstacles()[i].z_max_m);
    }
    const bool differs = a.obstacles().size() != c.obstacles().size() ||
                         a.obstacles()[0].cx_m != c.obstacles()[0].cx_m ||
                         a.terrain().height(20, 7) != c.terrain().height(20, 7);
    CHECK(differs);
  }
  CHECK_FALSE(parse_scene_kind("moon"));
}

TEST_CASE("scene kinds have their characteristic terrain", "[sim][scene]") {
  const Scene urban = Scene::generate(SceneKind::urban, 3);
  const Terrain& u = urban.terrain();
  const double curb =
      u.height(0, u.road_half_width_m + 0.01) - u.height(0, u.road_half_width_m - 0.01);
  CHECK(curb >= 0.10);
  CHECK(curb <= 0.18);
  const Scene slope = Scene::generate(SceneKind::slope, 3);
  const double grade = (slope.terrain().height(90, 0) - slope.terrain().height(80, 0)) / 10.0;
  CHECK(std::fabs(grade) >= 0.06);
  CHECK(std::fabs(grade) <= 0.14);
  CHECK(slope.terrain().height(0, 0) == 0.0);
  const Scene fences = Scene::generate(SceneKind::fences, 3);
  int far = 0;
  for (const Obstacle& o : fences.obstacles()) {
    const double r = std::hypot(o.cx_m, o.cy_m);
    far += r >= 28.0 && r <= 45.0 ? 1 : 0;
  }
  CHECK(far >= 10);
}

TEST_CASE("piecewise-linear profiles interpolate and hold their ends", "[sim][scene]") {
  Profile p;
  CHECK(p.value(3.0) == 0.0);
  p.add(-2.0, -1.0);
  p.add(0.0, 0.0);
  p.add(4.0, 2.0);
  CHECK(p.value(-5.0) == -1.0);
  CHECK(p.value(-1.0) == Approx(-0.5));
  CHECK(p.value(2.0) == Approx(1.0));
  CHECK(p.value(9.0) == 2.0);
  CHECK(p.max_slope() == Approx(0.5));
}

TEST_CASE("the terrain-shape scenes have the shape their name promises", "[sim][scene]") {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const Terrain e = Scene::generate(SceneKind::embankment, seed).terrain();
    for (double y : {-40.0, 40.0}) {  // fields 1.5-3 m under the road on both sides
      const double drop = e.height(5.0, 0.0) - e.height(5.0, y);
      CHECK(drop > 1.4);
      CHECK(drop < 3.2);
    }
    const Terrain b = Scene::generate(SceneKind::bank, seed).terrain();
    const double bank = std::max(b.height(0.0, 30.0), b.height(0.0, -30.0)) - b.height(0.0, 0.0);
    CHECK(bank > 1.9);  // a 2-5 m bank on one side
    const Terrain w = Scene::generate(SceneKind::bowl, seed).terrain();
    CHECK(std::max(w.height(0.0, 35.0), w.height(0.0, -35.0)) - w.height(0.0, 0.0) > 0.8);
    const Terrain c = Scene::generate(SceneKind::crest, seed).terrain();
    const double apex = c.curve_x.centre_m;
    CHECK(c.height(apex, 0.0) - c.height(apex + 40.0, 0.0) > 1.5);  // falls away ahead
    CHECK(c.height(apex, 0.0) - c.height(apex - 40.0, 0.0) > 1.5);  //   and behind
    const Scene g = Scene::generate(SceneKind::garage, seed);
    const Terrain& t = g.terrain();
    CHECK(t.height(t.along.at[3] + 5.0, 0.0) < -2.7);                         // garage floor
    CHECK(t.height(t.along.at[3] + 5.0, t.along_half_width_m + 1.0) == 0.0);  // street above
    bool ceiling = false;
    for (const Obstacle& o : g.obstacles())
      ceiling = ceiling || (o.cx_m > t.along.at[3] && o.z_min_m > -1.2 && o.z_min_m < 0.0);
    CHECK(ceiling);
  }
}
