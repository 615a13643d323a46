// Plausibility of the segment planes once Algorithm 1 has chosen them (plane_checks): the
// sensor-height prior.
#include <catch2/catch.hpp>

#include "plane_checks.hpp"

using namespace vlpground::detail;
using vlpground::GroundResult;
using vlpground::Plane;

namespace {

// Whether segment 0 keeps its ground after check_agreement when it alone has ground: a
// level plane at height plane_z_m, the partition centre 13 m behind the sensor and 9 m to
// its left (segment 0 lies past both), the sensor sensor_z_m over the vehicle frame's z = 0.
bool lone_plane_kept(float plane_z_m, float sensor_z_m) {
  SearchResult found;
  found.found = true;
  found.plane = {0, -1, -1, -1};
  found.score = {100, 0, 0, 0};
  GroundResult out;
  out.centre_x_m = -13.f;
  out.centre_y_m = 9.f;
  out.segments[0].has_ground = true;
  out.segments[0].plane = Plane{0.f, 0.f, 1.f, -plane_z_m};
  AgreementRules rules;
  rules.sensor_z = sensor_z_m;
  check_agreement(found, rules, out);
  return out.segments[0].has_ground;
}

}  // namespace

TEST_CASE("plane checks: with the mounting height known, no plane far over the wheels") {
  // The roofs of the cars around the vehicle in a jam, 1.32 m up (jam_s7003 at Hi-Res): the
  // sensor, 1.9 m over the wheels, is 0.58 m over them, inside the 0.5-5 m prior.
  CHECK_FALSE(lone_plane_kept(1.32f, 1.9f));
  // The ground under the wheels, and a ramp's plane extrapolated 1.1 m over the level
  // ground at its foot.
  CHECK(lone_plane_kept(0.f, 1.9f));
  CHECK(lone_plane_kept(1.1f, 1.9f));
  // The mounting height unknown (the sensor's own frame): the same roofs, 0.58 m under the
  // sensor, pass the prior.
  CHECK(lone_plane_kept(1.9f - 0.58f - 1.9f, 0.f));
  // ... and no plane only 0.4 m under the sensor, known or not.
  CHECK_FALSE(lone_plane_kept(1.5f, 1.9f));
  CHECK_FALSE(lone_plane_kept(-0.4f, 0.f));
}
