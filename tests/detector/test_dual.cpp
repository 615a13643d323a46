// Dual-return frames: the tangent method processes each distinct echo once (a last return
// repeating the strongest echo is its twin's point) and labels both cells alike.
#include <catch2/catch.hpp>
#include <cstdint>

#include "method.hpp"
#include "synthetic_scene.hpp"
#include "tangents.hpp"
#include "vlpground/detector/ground_detector.hpp"

using namespace vlpground;
using namespace vlpground::detail;

namespace {

// The street of test_detector as a dual frame: the last layer repeats the strongest echo,
// except in every 5th column, whose last echo lies 30 % farther along the same beam (as
// through foliage).
Frame dual_street() {
  test::Scene s;
  s.boxes.push_back({12.0, 12.4, -20.0, 20.0, -1.8, 3.0});
  s.boxes.push_back({-6.0, -2.0, 3.0, 4.8, -1.8, -0.3});
  Frame f = test::render(s).frame;
  f.meta.mode = ReturnMode::dual;
  for (int ring = 0; ring < kLasers; ++ring) {
    for (int col = 0; col < f.columns(); ++col) {
      const std::size_t i = f.index(ring, col);
      const bool distinct = col % 5 == 0 && f.layer[0].valid[i] != 0;
      const float scale = distinct ? 1.3f : 1.0f;
      f.layer[1].valid[i] = f.layer[0].valid[i];
      f.layer[1].x_m[i] = f.layer[0].x_m[i] * scale;
      f.layer[1].y_m[i] = f.layer[0].y_m[i] * scale;
      f.layer[1].z_m[i] = f.layer[0].z_m[i] * scale;
      f.layer[1].range_m[i] = f.layer[0].range_m[i] * scale;
      f.same_echo[i] = static_cast<std::uint8_t>(!distinct && f.layer[0].valid[i] != 0);
    }
  }
  return f;
}

std::size_t count(const std::vector<std::uint8_t>& v, std::uint8_t value) {
  return static_cast<std::size_t>(std::count(v.begin(), v.end(), value));
}

}  // namespace

TEST_CASE("a deduplicated cloud holds each distinct echo once", "[detector][dual]") {
  const Frame f = dual_street();
  Cloud full, dedup;
  build_cloud(f, Extrinsics{}, false, full);
  build_cloud(f, Extrinsics{}, true, dedup);
  const std::size_t strongest = count(f.layer[0].valid, 1), twins = count(f.same_echo, 1);
  const std::size_t last = count(f.layer[1].valid, 1);
  REQUIRE(twins > 10000);
  REQUIRE(last > twins);
  CHECK(full.size() == strongest + last);
  CHECK(dedup.size() == strongest + last - twins);
  CHECK(count(dedup.twin, 1) == twins);
  CHECK(dedup.last_begin == strongest);
  // Every last-layer cell, in (ring, column) order, maps to the point holding its echo.
  REQUIRE(dedup.last_rows.size() == last);
  std::size_t k = 0;
  for (int ring = 0; ring < kLasers; ++ring) {
    for (int col = 0; col < f.columns(); ++col) {
      const std::size_t i = f.index(ring, col);
      if (f.layer[1].valid[i] == 0) continue;
      const std::uint32_t p = dedup.last_rows[k++];
      CHECK(dedup.cell[p] == i);
      CHECK(dedup.x[p] == f.layer[1].x_m[i]);
      CHECK(dedup.z[p] == f.layer[1].z_m[i]);
      CHECK((dedup.layer[p] == 1) == (f.same_echo[i] == 0));
    }
  }
}

TEST_CASE("distinct last returns keep the tangents of their full row", "[detector][dual]") {
  const Frame f = dual_street();
  Cloud full, dedup;
  build_cloud(f, Extrinsics{}, false, full);
  build_cloud(f, Extrinsics{}, true, dedup);
  TangentParams params;
  params.column_angle_rad = 2.f * static_cast<float>(M_PI) / static_cast<float>(f.columns());
  Tangents t_full, t_dedup;
  compute_tangents(full, params, t_full);
  compute_tangents(dedup, params, t_dedup);
  // Points of both clouds by cell: strongest points are the same; a distinct last return
  // walks its row through the twins, which are the same echoes the full row holds.
  std::size_t compared = 0;
  for (std::size_t a = 0, b = 0; a < full.size() && b < dedup.size(); ++a) {
    if (full.layer[a] != dedup.layer[b] || full.cell[a] != dedup.cell[b]) continue;
    INFO("cell " << full.cell[a] << " layer " << int{full.layer[a]});
    CHECK(t_full.valid[a] == t_dedup.valid[b]);
    CHECK(t_full.x[a] == t_dedup.x[b]);
    CHECK(t_full.z[a] == t_dedup.z[b]);
    compared += full.layer[a];
    ++b;
  }
  CHECK(compared == dedup.size() - dedup.last_begin);
  CHECK(compared > 1000);
}

TEST_CASE("a last return repeating the strongest echo gets its label and height",
          "[detector][dual]") {
  const Frame f = dual_street();
  GroundDetector det;
  GroundResult r;
  det.detect(f, r);
  std::size_t twins = 0;
  for (int ring = 0; ring < kLasers; ++ring) {
    for (int col = 0; col < f.columns(); ++col) {
      const std::size_t i = f.index(ring, col);
      if (f.layer[1].valid[i] == 0) {
        CHECK(r.label[1][i] == static_cast<std::uint8_t>(GroundLabel::no_return));
        continue;
      }
      CHECK(r.label[1][i] != static_cast<std::uint8_t>(GroundLabel::no_return));
      if (f.same_echo[i] != 0) {
        ++twins;
        CHECK(r.label[1][i] == r.label[0][i]);
        CHECK(r.height_m[1][i] == r.height_m[0][i]);
      }
    }
  }
  CHECK(twins > 10000);
  CHECK(r.ground_returns == count(r.label[0], 1) + count(r.label[1], 1));
}
