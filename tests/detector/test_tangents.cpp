// Ring tangents (paper Sec. III-A) and the eq. 3 inlier test.
#include <catch2/catch.hpp>
#include <cmath>

#include "hypotheses.hpp"
#include "tangents.hpp"

using namespace vlpground;
using namespace vlpground::detail;

namespace {

// Appends one return of row (layer 0, `ring`) at column `col`.
void add(Cloud& c, int ring, int col, float x, float y, float z) {
  c.x.push_back(x);
  c.y.push_back(y);
  c.z.push_back(z);
  c.range_xy.push_back(std::hypot(x, y));
  c.cell.push_back(static_cast<std::uint32_t>(ring * 4096 + col));
  c.layer.push_back(0);
  c.ring.push_back(static_cast<std::uint16_t>(ring));
  c.column.push_back(static_cast<std::uint16_t>(col));
}

// A ring on the plane z = a x + b y + c at radius r, columns [0, n) over `deg` degrees,
// skipping the columns in `holes`.
Cloud ring_on_plane(float a, float b, float c0, float r, int n, float deg,
                    std::initializer_list<int> holes = {}) {
  Cloud c;
  for (int col = 0; col < n; ++col) {
    if (std::find(holes.begin(), holes.end(), col) != holes.end()) continue;
    const float az =
        deg * static_cast<float>(M_PI) / 180.f * static_cast<float>(col) / static_cast<float>(n);
    const float x = r * std::cos(az), y = r * std::sin(az);
    add(c, 0, col, x, y, a * x + b * y + c0);
  }
  return c;
}

}  // namespace

TEST_CASE("tangent of a ring on a plane is perpendicular to its normal", "[detector][tangent]") {
  const float a = 0.08f, b = -0.05f;
  const Cloud cloud = ring_on_plane(a, b, -1.8f, 12.f, 200, 40.f);
  Tangents t;
  compute_tangents(cloud, TangentParams{}, t);
  const float norm = std::sqrt(a * a + b * b + 1);
  const Plane p{-a / norm, -b / norm, 1 / norm, 1.8f / norm};
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    REQUIRE(t.valid[i] == 1);
    CHECK(std::abs(p.nx * t.x[i] + p.ny * t.y[i] + p.nz * t.z[i]) < 1e-3f);
    CHECK(t.x[i] * t.x[i] + t.y[i] * t.y[i] + t.z[i] * t.z[i] == Approx(1.0f).epsilon(1e-4));
  }
}

TEST_CASE("invalid cells are skipped, a lone return has no tangent", "[detector][tangent]") {
  Cloud cloud = ring_on_plane(0, 0, -1.8f, 10.f, 60, 10.f, {20, 21, 22});
  add(cloud, 1, 5, 3.f, 1.f, -1.f);  // alone on ring 1
  Tangents t;
  compute_tangents(cloud, TangentParams{}, t);
  for (std::size_t i = 0; i + 1 < cloud.size(); ++i) {
    REQUIRE(t.valid[i] == 1);
    CHECK(std::abs(t.z[i]) < 1e-3f);
  }
  CHECK(t.valid.back() == 0);
  CHECK(t.z.back() == kNoTangentZ);  // fails eq. 3 for any near-horizontal plane
}

TEST_CASE("neighbours across a range discontinuity are refused", "[detector][tangent]") {
  // Ring crossing from a wall at 8 m (vertical, along y) to one at 15 m: the columns next
  // to the jump must take their tangent from their own side only.
  Cloud cloud;
  for (int col = 0; col < 40; ++col) {
    const float y = 0.05f * static_cast<float>(col);
    const float x = col < 20 ? 8.f : 15.f;
    add(cloud, 3, col, x, y, 0.2f * y);  // rising along y: a tilted line on each wall
  }
  Tangents t;
  compute_tangents(cloud, TangentParams{}, t);
  const float expect_z = 0.2f / std::sqrt(1.04f);
  for (int i : {18, 19, 20, 21}) {
    REQUIRE(t.valid[static_cast<std::size_t>(i)] == 1);
    CHECK(std::abs(t.x[static_cast<std::size_t>(i)]) < 1e-4f);  // never points across
    CHECK(t.z[static_cast<std::size_t>(i)] == Approx(expect_z).epsilon(1e-3));
  }
}

TEST_CASE("eq. 3: distance and tangent angle tests", "[detector][eq3]") {
  const Plane p{0, 0, 1, 1.8f};  // z = -1.8
  const float eps = 0.2f, sin_delta = std::sin(10.f * static_cast<float>(M_PI) / 180.f);
  CHECK(eq3_inlier(p, 5, 2, -1.7f, 1, 0, 0, eps, sin_delta));
  CHECK_FALSE(eq3_inlier(p, 5, 2, -1.55f, 1, 0, 0, eps, sin_delta));  // too far
  // Tangent 15 deg off the plane fails, 5 deg passes, whatever the sign.
  const float d15 = 15.f * static_cast<float>(M_PI) / 180.f;
  const float d5 = 5.f * static_cast<float>(M_PI) / 180.f;
  CHECK_FALSE(eq3_inlier(p, 5, 2, -1.8f, std::cos(d15), 0, std::sin(d15), eps, sin_delta));
  CHECK(eq3_inlier(p, 5, 2, -1.8f, std::cos(d5), 0, -std::sin(d5), eps, sin_delta));
  // Agrees with the literal |pi/2 - arccos(n.t)| < delta on a sweep of angles.
  for (int k = -89; k <= 89; ++k) {
    const float ang = (static_cast<float>(k) + 0.5f) * static_cast<float>(M_PI) / 180.f;
    const float tz = std::sin(ang), tx = std::cos(ang);
    const bool literal = std::abs(static_cast<float>(M_PI) / 2 - std::acos(tz)) <
                         10.f * static_cast<float>(M_PI) / 180.f;
    CHECK(eq3_inlier(p, 0, 0, -1.8f, tx, 0, tz, eps, sin_delta) == literal);
  }
}

TEST_CASE("least-squares plane fit recovers a plane", "[detector][fit]") {
  PlaneFit fit;
  for (int i = 0; i < 50; ++i) {
    const float x = static_cast<float>(i % 10), y = static_cast<float>(i / 10);
    fit.add(x, y, 0.1f * x - 2.f);
  }
  Plane p;
  REQUIRE(fit.solve(p));
  const float n = std::sqrt(1.01f);
  CHECK(p.nx == Approx(-0.1f / n).margin(1e-4));
  CHECK(p.nz == Approx(1.f / n).margin(1e-4));
  CHECK(p.d / p.nz == Approx(2.f).margin(1e-3));
}
