// Terrain refinement (terrain_cells.hpp): the histogram window search against a plain
// reference, the height-plane form, and the config switch back to the paper's method.
#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <vector>

#include "synthetic_scene.hpp"
#include "terrain_cells.hpp"
#include "vlpground/detector/ground_detector.hpp"

using namespace vlpground;
using namespace vlpground::detail;

TEST_CASE("densest_window agrees with the plain reference", "[detector][terrain]") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> count(0, 12), sparse(0, 3);
  for (int trial = 0; trial < 3000; ++trial) {
    const int bins = 1 + trial % 64;
    std::vector<std::uint16_t> hist(static_cast<std::size_t>(bins));
    for (auto& h : hist) h = static_cast<std::uint16_t>(trial % 3 == 0 ? sparse(rng) : count(rng));
    const int width = 1 + trial % 8;
    const float share = static_cast<float>(trial % 4) * 0.33f;
    const int min_count = trial % 10;
    INFO("trial " << trial);
    CHECK(densest_window(hist.data(), bins, width, share, min_count) ==
          densest_window_reference(hist.data(), bins, width, share, min_count));
  }
}

TEST_CASE("densest_window prefers the lowest window that qualifies", "[detector][terrain]") {
  const std::uint16_t hist[] = {0, 3, 0, 0, 9, 9, 0, 5, 5};
  CHECK(densest_window(hist, 9, 2, 1.f, 1) == 4);   // the densest
  CHECK(densest_window(hist, 9, 2, 0.f, 3) == 0);   // the lowest with 3
  CHECK(densest_window(hist, 9, 2, 0.5f, 1) == 3);  // the lowest with half the densest
  CHECK(densest_window(hist, 9, 2, 0.f, 19) == -1);
  CHECK(densest_window(hist, 1, 2, 0.f, 0) == -1);  // narrower than a window
}

TEST_CASE("HeightPlane is the plane's height field", "[detector][terrain]") {
  const Plane p{0.1f, -0.2f, 0.9747f, 1.5f};  // n.p + d = 0
  const HeightPlane h = HeightPlane::from(p);
  for (const float x : {-10.f, 0.f, 7.f}) {
    for (const float y : {-3.f, 4.f}) {
      const float z = h.at(x, y);
      CHECK(p.nx * x + p.ny * y + p.nz * z + p.d == Approx(0.f).margin(1e-5));
    }
  }
}

TEST_CASE("climbs_object_line: a ring line on an object past level ground, not a bend",
          "[detector][terrain]") {
  // fences_s704: ring 5 on the ground 22 m out, ring 6 on a fence 0.6 m up 3 m beyond it,
  // the fit through both turning the level reference by 0.2.
  const HeightPlane level{0.f, 0.005f, 0.f};
  const HeightPlane fit{-4.4f, 0.2f, 0.f};
  const RingLine ground{21.8f, 0.02f}, fence{24.8f, 0.62f};
  CHECK(climbs_object_line(level, fit, ground, fence));
  // A hillside bending on from a gradient of its own.
  CHECK_FALSE(climbs_object_line({0.f, 0.04f, 0.f}, {-4.4f, 0.24f, 0.f}, ground, fence));
  CHECK(climbs_object_line({0.f, 0.02f, 0.f}, {-4.4f, 0.22f, 0.f}, ground, fence));
  // The nearer ring off the reference: the reference lags, the fit corrects it.
  CHECK_FALSE(climbs_object_line(level, fit, {21.8f, 0.2f}, {24.8f, 0.82f}));
  CHECK(climbs_object_line(level, fit, {21.8f, 0.1f}, {24.8f, 0.72f}));
  // The farther ring only a little higher: terrain curving gently.
  CHECK_FALSE(climbs_object_line(level, fit, ground, {24.8f, 0.3f}));
  CHECK(climbs_object_line(level, fit, ground, {24.8f, 0.35f}));
  // Rings crowding on a face (a bank's): less than a metre apart.
  CHECK_FALSE(climbs_object_line(level, fit, ground, {22.7f, 0.62f}));
  CHECK(climbs_object_line(level, fit, ground, {22.9f, 0.62f}));
  // A fit that hardly turns the reference: no climb.
  CHECK_FALSE(climbs_object_line(level, {-0.4f, 0.09f, 0.f}, ground, fence));
  CHECK(climbs_object_line(level, {-0.4f, 0.12f, 0.f}, ground, fence));
}

TEST_CASE("terrain refinement leaves a plane the paper's method explains alone",
          "[detector][terrain]") {
  test::Scene scene;
  scene.boxes.push_back({8, 12, 2, 4, -1.8, 0.0});  // a car-sized box
  const test::SceneFrame sf = test::render(scene);
  DetectorConfig on, off;
  off.terrain_refinement = false;
  GroundDetector a(on), b(off);
  GroundResult ra, rb;
  a.detect(sf.frame, ra);
  b.detect(sf.frame, rb);
  CHECK(ra.label[0] == rb.label[0]);
  CHECK(ra.ground_returns > 0);
}

TEST_CASE("refinement_cell_m is validated", "[detector][terrain]") {
  DetectorConfig c;
  c.refinement_cell_m = 0.5;  // under the bin size
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("refinement_cell_m"));
  c.refinement_cell_m = 25;
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("refinement_cell_m"));
  c.refinement_cell_m = 4;
  CHECK_NOTHROW(c.validate());
}
