// Column profiles, the walk down each column (docs/detector.md, "Column profiles", rules 1,
// 2, 3 and 6): continuing the profile, past obstacles, nearer returns, rays that passed.
#include <catch2/catch.hpp>
#include <cmath>
#include <utility>
#include <vector>

#include "column_scan.hpp"

using namespace vlpground::detail;
using namespace column_scan;

TEST_CASE("column profiles follow a bank, a levee's fields and stop at walls and boxes",
          "[detector][profiles]") {
  const Scan scan = make_scan();
  const std::vector<float> none(scan.cloud.size(), std::nanf(""));
  const auto [ground, height] = label(scan, none, none);

  int bank = 0, fields = 0;
  for (std::size_t i = 0; i < scan.cloud.size(); ++i) {
    INFO("ring " << scan.cloud.ring[i] << " column " << scan.cloud.column[i] << " z "
                 << scan.cloud.z[i]);
    const bool wall_beyond_ground =
        wall_column(scan.cloud.column[i]) && scan.cloud.range_xy[i] < 12.f;
    // Ring 4 (12 m) meets the fields in column 0 only, the levee's side in the shadow on
    // both sides of it: a lone return with the sky on both sides across the frame's edge,
    // standing out (rule 5) as anywhere else on the ring.
    const bool lone_return = scan.cloud.ring[i] == 4 && scan.cloud.z[i] < -1.f;
    if (lone_return) {
      CHECK(ground[i] == 0);
    } else if (scan.truth[i] == 2) {
      CHECK(ground[i] == 0);
    } else if (!wall_beyond_ground) {
      CHECK(ground[i] == 1);
      if (scan.cloud.z[i] == 0.f) CHECK(std::abs(height[i]) < 0.05f);  // the road
    }
    bank += scan.truth[i] == 1 && scan.cloud.y[i] < -6.f && ground[i] == 1;
    fields += scan.truth[i] == 1 && scan.cloud.z[i] < -1.f && ground[i] == 1;
  }
  CHECK(bank > 150);
  CHECK(fields > 200);
}

// The column `s` (one return per ring, column 0), then a wall `wall_r` out: its foot on the
// column's climb extrapolated at `gradient` from its last return, the next ring `face_m`
// over the foot at the same distance (a steep pair), both obstacles.
static Scan climb_then_wall(Scan s, float gradient, float wall_r, float face_m) {
  const int ring = static_cast<int>(s.truth.size());
  const float foot = s.cloud.z.back() + gradient * (wall_r - s.cloud.range_xy.back());
  add(s, ring, 0, wall_r, foot, 2);
  add(s, ring + 1, 0, wall_r, foot + face_m, 2);
  return s;
}

TEST_CASE("column profiles: the steep band trusts only a short climb past the last ground",
          "[detector][profiles]") {
  // Sim bank (seed 5): a bank climbing at 0.21 seen to 18 m; 9 m farther a shed's wall on
  // the bank top (two rings at one distance, a steep pair), its lower return on the bank's
  // slope extrapolated by chance. The extrapolated climb (1.9 m) is only a guess there.
  auto bank_then_wall = [](float wall_r) {
    const std::vector<float> r{6.f, 8.f, 10.f, 12.5f, 15.f, 18.f};
    std::vector<float> z;
    for (const float x : r) z.push_back(0.21f * (x - 6.f));
    return climb_then_wall(ground_column(r, z), 0.21f, wall_r, 1.2f);
  };
  const Scan far = bank_then_wall(27.f);
  CHECK(label(far).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 1, 1, 0, 0});
  // The foot of a wall 2 m past the last ground return (a 0.4 m climb) is still ground.
  const Scan near = bank_then_wall(20.f);
  CHECK(label(near).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 1, 1, 1, 0});
}

TEST_CASE("column profiles: past a gentle climb the steep band trusts only 0.2 m of it",
          "[detector][profiles]") {
  // Sim fences_s3805 (5 Hz, frame 4, column 1229): flat ground to ring 4 (16.4 m); ring 5
  // meets a fence's foot 21.1 m out, 0.16 m up (a gentle rise, 0.034); ring 6 passes over
  // the fence and meets a facade 30 m out at 0.46 m, ring 7 the facade over it. The gentle
  // gradient carried 8.9 m lifts the profile 0.3 m, onto the facade's foot.
  auto rise_then_wall = [](float wall_r) {
    Scan s = ground_column({7.4f, 8.6f, 10.25f, 12.6f, 16.4f}, {0.f, 0.f, 0.f, 0.f, 0.f});
    add(s, 5, 0, 21.1f, 0.16f, 2);
    return climb_then_wall(std::move(s), 0.034f, wall_r, 1.05f);
  };
  const Scan far = rise_then_wall(30.f);
  CHECK(label(far).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 1, 1, 0, 0});
  // A wall 3 m past the rise (a 0.1 m climb): its foot is still ground.
  const Scan near = rise_then_wall(24.f);
  CHECK(label(near).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 1, 1, 1, 0});
}

TEST_CASE("column profiles: rings crowding on a bank face close by still move the profile",
          "[detector][profiles]") {
  // A bank face rising at 0.55 from 6.3 m: ring 1 is only 0.28 m past ring 0 (too close to
  // take a gradient from), but it moves the profile's end; from ring 0, ring 2 would be
  // over the allowance and the face lost.
  Scan s;
  const float r[] = {6.27f, 6.55f, 6.88f, 7.27f, 7.61f}, z[] = {0.1f, 0.26f, 0.44f, 0.63f, 0.84f};
  for (int ring = 0; ring < 5; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
  CHECK(label(s).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 1});
}

TEST_CASE("column profiles: past a car the ground resumes at a gentle slope, not on its roof",
          "[detector][profiles]") {
  // Ring 4 either the car's roof at 9.5 m, 1.5 m up, or terrain rising at 0.05 from the
  // last ground: 0.7 m up at 20 m, more than the 0.25 + 0.03 x 14 m allowed past an obstacle.
  CHECK(label(car_then(9.5f, 1.5f, 2)).ground == std::vector<std::uint8_t>{1, 0, 0, 0, 0});
  CHECK(label(car_then(20.f, 0.7f, 1)).ground == std::vector<std::uint8_t>{1, 0, 0, 0, 1});
}

TEST_CASE("column profiles: no resume on the start's guess where level 2 disagrees",
          "[detector][profiles]") {
  // A car side next to the sensor (rings 0-3 at 5.8 m, steep), then rings 4 and 5 at
  // 19.5 m and 25.5 m, 0.88 m and 1.46 m up: gentle slopes from the start under the sensor
  // (0.045, 0.057), over the allowance past an obstacle. Car roofs in a jam when the level-2
  // surface is as far under them; ground when that surface runs through them (or is
  // unknown).
  const auto roof_or_ground = [](float level2_h) {
    Scan s;
    for (int ring = 0; ring <= 3; ++ring) {
      add(s, ring, 0, 5.8f, 0.3f + 0.25f * static_cast<float>(ring), 2);
    }
    add(s, 4, 0, 19.5f, 0.88f, 2);
    add(s, 5, 0, 25.5f, 1.46f, 2);
    std::vector<float> level2(s.cloud.size(), 0.f);
    level2[4] = std::isnan(level2_h) ? level2_h : level2_h * 0.88f;
    level2[5] = std::isnan(level2_h) ? level2_h : level2_h * 1.46f;
    return label(s, level2).ground[4];
  };
  CHECK(roof_or_ground(1.f) == 0);
  CHECK(roof_or_ground(0.f) == 1);
  CHECK(roof_or_ground(std::nanf("")) == 1);
}

TEST_CASE("column profiles: a canopy in front of ground already walked is not ground",
          "[detector][profiles]") {
  Scan s;
  // One column rising gently out to 40 m, then the top ring hits a tree crown at 8 m,
  // level with the far ground: compared with the profile at 8 m it is 2.8 m up.
  const float r[] = {6.f, 10.f, 20.f, 40.f}, z[] = {0.f, 0.2f, 1.f, 3.f};
  for (int ring = 0; ring < 4; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
  add(s, 4, 0, 8.f, 2.9f, 2);
  const auto [ground, height] = label(s);
  CHECK(ground == std::vector<std::uint8_t>{1, 1, 1, 1, 0});
  CHECK(height[4] == Approx(2.8f).margin(0.01f));
}

TEST_CASE("column profiles: past an obstacle a level-1 plane that explains its cell is trusted",
          "[detector][profiles]") {
  // Ground at 20 m 1.0 m up past the car: too steep a resume (0.07 from the last ground
  // return) and over the allowance past an obstacle, unless a level-1 plane that explains
  // its cell runs through it.
  const Scan s = car_then(20.f, 1.0f, 1);
  CHECK(label(s).ground[4] == 0);
  std::vector<float> plane(s.cloud.size(), std::nanf(""));
  plane[4] = 0.05f;
  CHECK(label(s, {}, plane).ground[4] == 1);
}

TEST_CASE("column profiles: a return a lower ring's ray passes under is not ground",
          "[detector][profiles]") {
  // Past the crest the ground falls away out of sight; rings 5 and 6 hit a car, ring 7 a
  // bush top at 12 m, 1.65 m up, which the walk alone takes (under the extrapolated face,
  // 0.45 m over the last ground return).
  const auto bush = [](float car_r, float z5, float z6) {
    Scan s = bank_face();
    add(s, 5, 0, car_r, z5, 2);
    add(s, 6, 0, car_r, z6, 2);
    add(s, 7, 0, 12.f, 1.65f, 2);
    return label(s).ground;
  };
  // The car at 20 m: ring 6's ray is 1.38 m up at 12 m, under the bush top: no ground.
  CHECK(bush(20.f, 0.8f, 1.1f) == std::vector<std::uint8_t>{1, 1, 1, 1, 1, 0, 0, 0});
  // The car at 11.5 m: no ray reaches 12 m, the walk's answer stands.
  CHECK(bush(11.5f, 1.2f, 1.4f)[7] == 1);
}

TEST_CASE("column profiles: the top of a steep pair is not the foot of a wall",
          "[detector][profiles]") {
  // A wall at 11 m: ring 5 at 1.2 m, ring 6 right above it exactly on the extrapolated
  // face (the foot-of-a-wall band would take it); ring 5's return is 0.3 m under it.
  Scan s = bank_face();
  add(s, 5, 0, 11.f, 1.2f, 2);
  add(s, 6, 0, 11.05f, 1.2f + 0.3f * 1.05f, 2);
  CHECK(label(s).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 1, 0, 0});
}

TEST_CASE("column profiles: no climb past a ring that went to the sky",
          "[detector][profiles]") {
  // Rings 5 and 6 have no return; ring 7 hits a crown at 30 m, 5 m up (3.8 m over the last
  // ground return, under the extrapolated face: the walk alone takes it as a lower
  // surface). Either ring's ray would have hit any surface joining the two.
  const auto crown_past_sky = [](bool neighbour_hit_short) {
    Scan s = bank_face();
    add(s, 7, 0, 30.f, 5.f, 2);
    // In column 1, rings 5 and 6 hit something at 11 m: in column 0 they may have dropped out.
    if (neighbour_hit_short) {
      add(s, 5, 1, 11.f, 2.f, 2);
      add(s, 6, 1, 11.f, 2.4f, 2);
    }
    return label(s).ground[5];
  };
  CHECK(crown_past_sky(false) == 0);
  CHECK(crown_past_sky(true) == 1);
}

TEST_CASE("column profiles: a return a ring between it and the last ground returned past is none",
          "[detector][profiles]") {
  // Sim fences_s1003 (frame 0, column 10): ring 0 on a barrier's top 4.6 m out (taken as a
  // kink, later dropped), rings 1-4 on a face 5.5 m out. Ring 2 lies on the profile through
  // ring 0 (the face's foot), but ring 1 returned from its distance, 0.199 m under it.
  CHECK(label_column({{0, 4.6f, 0.701f, 0.79f},
                      {1, 5.48f, 0.667f, 0.75f},
                      {2, 5.48f, 0.866f, 0.95f},
                      {3, 5.48f, 1.06f, 1.15f},
                      {4, 5.46f, 1.256f, 1.34f},
                      {5, 16.76f, 0.459f, 0.02f},
                      {6, 35.53f, 0.062f, 0.f}}) == std::vector<int>{0, 0, 0, 0, 0, 1, 1});
  // Sim garage_s804_tilt (frame 0, column 959): a wall 5.2 m out before any ground, on a
  // level-1 plane; ring 1 was its foot from the start (rule 1's plane clause), but ring 0
  // returned from its distance, 0.198 m under it.
  const std::vector<ColumnReturn> wall = {{0, 5.24f, 0.138f, -0.12f}, {1, 5.24f, 0.336f, 0.03f},
                                          {2, 5.2f, 0.538f, 0.28f},   {3, 5.22f, 0.722f, 0.46f},
                                          {4, 5.2f, 0.913f, 0.65f},   {5, 16.53f, 0.782f, 0.f},
                                          {6, 25.1f, 1.142f, 0.f}};
  CHECK(label_column_on_plane(wall) == std::vector<int>{0, 0, 0, 0, 0, 1, 1});
  // A level road whose ring 2 dropped out (as a real sensor does on dark asphalt over whole
  // stretches of columns: vlp16_outdoor_600rpm): a ring gone to the sky only vetoes a climb.
  CHECK(label_column(
            {{0, 6.f, 0.f, 0.f}, {1, 7.f, 0.f, 0.f}, {3, 10.5f, 0.f, 0.f}, {4, 13.5f, 0.f, 0.f}}) ==
        std::vector<int>{1, 1, 1, 1});
}

TEST_CASE("column profiles: a wall met by the column's lowest return over the start is no foot",
          "[detector][profiles]") {
  // A column before any ground, where a level-1 plane explaining the cell passes through
  // return `on_plane` alone; its labels.
  const auto labels = [](const std::vector<ColumnReturn>& column, std::size_t on_plane) {
    std::vector<float> plane(column.size(), std::nanf(""));
    plane[on_plane] = 0.02f;
    return label_column(column, plane);
  };
  // Sim garage_s105 (frame 2, column 259): rings 0-5 on a wall 4.7 m out, ring 0 0.65 m
  // over the vehicle's ground (0.70 m over the hidden foot) where a level-1 plane passes.
  CHECK(labels({{0, 4.66f, 0.654f, 0.02f},
                {1, 4.63f, 0.831f, 0.2f},
                {2, 4.67f, 0.991f, 0.35f},
                {3, 4.65f, 1.162f, 0.53f},
                {4, 4.66f, 1.324f, 0.69f},
                {5, 4.69f, 1.485f, 0.84f},
                {7, 9.41f, 1.727f, 0.78f},
                {8, 9.42f, 2.055f, 1.1f}},
               0) == std::vector<int>{0, 0, 0, 0, 0, 0, 0, 0});
  // Sim embankment_s105 (frame 0, column 467): the column's first return under the start,
  // on a field 2.7 m below the levee, with a post on it: the plane's foot stands.
  CHECK(labels({{0, 17.31f, -2.735f, 0.f}, {1, 17.33f, -2.1f, 0.64f}, {2, 23.86f, -2.738f, 0.f}},
               0)[0] == 1);
  // Sim garage_s906 (frame 0, column 1471): a ramp's wall 7 m out (rings 0-7), then a
  // facade 23 m out on the street 2.35 m up: its foot (ring 8) is not the column's first
  // return.
  std::vector<ColumnReturn> ramp;
  for (int ring = 0; ring < 8; ++ring) {
    const auto up = static_cast<float>(ring);
    ramp.push_back({ring, 7.f, 0.092f + 0.248f * up, -0.68f + 0.25f * up});
  }
  ramp.push_back({8, 22.78f, 2.349f, 0.f});
  ramp.push_back({9, 23.3f, 3.171f, 0.77f});
  ramp.push_back({10, 23.17f, 3.976f, 1.58f});
  CHECK(labels(ramp, 8) == std::vector<int>{0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0});
  // Sim garage_s907_5hz (frame 3, column 3305): rings 0-4 on a ramp's wall 6.2 m out, ring
  // 0 only 0.28 m over the vehicle's ground (0.67 m over the hidden foot), within the 0.5 m
  // the plane clause allows elsewhere; rings 5-7 on the street beyond.
  CHECK(labels({{0, 6.2f, 0.279f, 0.06f},
                {1, 6.2f, 0.506f, 0.355f},
                {2, 6.18f, 0.735f, 0.583f},
                {3, 6.21f, 0.951f, 0.799f},
                {4, 6.19f, 1.173f, 1.021f},
                {5, 15.75f, 0.554f, 0.f},
                {6, 22.02f, 0.776f, 0.003f},
                {7, 36.73f, 1.288f, -0.001f}},
               0) == std::vector<int>{0, 0, 0, 0, 0, 1, 1, 1});
  // Sim urban_s1_hires (frame 1, column 313): a building's foot on a pavement 0.18 m over
  // the road, met by ring 0 (Hi-Res, 10 m out), its face above: the foot stands.
  CHECK(labels({{0, 10.16f, 0.18f, 0.017f},
                {1, 10.17f, 0.42f, 0.256f},
                {2, 10.14f, 0.664f, 0.501f},
                {3, 10.17f, 0.899f, 0.735f},
                {4, 10.16f, 1.136f, 0.973f}},
               0) == std::vector<int>{1, 0, 0, 0, 0});
}

TEST_CASE("column profiles: a return the face goes on under is no wall's foot",
          "[detector][profiles]") {
  // Sim hills_s1005 (frame 0, column 375): rings 0-3 on the vehicle's hill out to 11 m,
  // rings 5-8 on a tree 36.4-37 m out standing in a dip past the crest, 3.7 m under the
  // hill. Ring 6 lies on the hill's profile extrapolated (within the steep band), but ring 5
  // met the same face 1.27 m lower. h: over the level-2 surface, which is the level-1 plane.
  const std::vector<ColumnReturn> tree = {
      {0, 6.69f, 0.158f, 0.031f},   {1, 7.66f, 0.181f, 0.023f},    {2, 8.99f, 0.201f, 0.001f},
      {3, 11.09f, 0.191f, -0.077f}, {5, 36.42f, -1.242f, -0.043f}, {6, 36.58f, 0.025f, 1.23f},
      {7, 36.72f, 1.3f, 2.51f},     {8, 36.98f, 2.585f, 3.802f}};
  CHECK(label_column_on_plane(tree) == std::vector<int>{1, 1, 1, 1, 0, 0, 0, 0});
  // vlp16_1200rpm_productbyte21 (indoor, frame 1, 345.8 degrees): ring 0 on the floor
  // 6.58 m out, ring 1 on a wall 0.18 m beyond it, 0.20 m up, where a level-1 plane passes
  // (rule 1's plane clause took it); rings 2-4 on the wall. The floor return is the wall's
  // foot, ring 1 no second one.
  const std::vector<ColumnReturn> wall = {{0, 6.58f, -0.03f, 0.f},
                                          {1, 6.76f, 0.171f, 0.2f},
                                          {2, 6.76f, 0.414f, 0.44f},
                                          {3, 6.76f, 0.656f, 0.69f},
                                          {4, 6.72f, 0.901f, 0.93f}};
  std::vector<float> plane_at_ring1(wall.size(), std::nanf(""));
  plane_at_ring1[1] = 0.03f;
  CHECK(label_column(wall, plane_at_ring1) == std::vector<int>{1, 0, 0, 0, 0});
  // A wall at the top of a climb, its foot on the profile: the ring under the foot met the
  // climb 0.25 m lower but 1.25 m nearer, not the face: the foot stands.
  CHECK(label_column({{0, 5.f, 0.f, 0.f},
                      {1, 6.25f, 0.25f, 0.f},
                      {2, 7.5f, 0.5f, 0.f},
                      {3, 7.5f, 1.1f, 0.6f},
                      {4, 7.5f, 1.7f, 1.2f}}) == std::vector<int>{1, 1, 1, 0, 0});
}

TEST_CASE("column profiles: a return under the profile but above the last ground keeps rising",
          "[detector][profiles]") {
  // A hill's shoulder (sim hills, seed 4): the climb at 0.32 flattens to 0.2 between
  // rings 10 and 11 (ring 11 is 1 m under the extrapolated climb, a "lower surface"), and
  // ring 12 rises on at 0.26 past it. Levelled at ring 11, ring 12 would be 2.7 m over.
  const float r[] = {6.59f, 7.42f, 8.29f, 9.33f, 10.36f, 11.49f, 12.72f,
                     14.06f, 15.60f, 17.37f, 19.93f, 28.48f, 38.90f};
  const float z[] = {0.02f, 0.07f, 0.17f, 0.30f, 0.51f, 0.77f, 1.11f,
                     1.53f, 2.05f, 2.68f, 3.51f, 5.26f, 7.93f};
  Scan s;
  for (int ring = 0; ring < 13; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
  // The level-2 surface follows the ground (the single-rise check stays out of it).
  CHECK(label(s, std::vector<float>(s.cloud.size(), 0.f)).ground ==
        std::vector<std::uint8_t>(13, 1));
  // Fields below a levee stay level: past the levee's side ring 2 is on the fields, and
  // ring 3 on them too (a falling step keeps the lower surface level).
  Scan levee;
  const float lr[] = {6.f, 8.f, 14.f, 18.f}, lz[] = {0.f, -0.6f, -2.f, -2.f};
  for (int ring = 0; ring < 4; ++ring) add(levee, ring, 0, lr[ring], lz[ring], 1);
  CHECK(label(levee, std::vector<float>(levee.cloud.size(), 0.f)).ground ==
        std::vector<std::uint8_t>(4, 1));
}

TEST_CASE("column profiles: past an obstacle on the start's guess, the ground may have bent",
          "[detector][profiles]") {
  // A hill behind a bush (sim hills, seed 4, Puck Hi-Res): the lowest ring meets the ground
  // at 8.5 m, rings 1-6 the bush just behind it, and rings 7-11 the hill rising at 0.26-0.33
  // from 13.8 m. The profile's gradient is only the chord from the level start (0.03): ring 7
  // is 1.2 m over it, far over the allowance past an obstacle, and 0.22 steeper than it.
  // Terrain curving up bends the chord that much over the 11 m since the start; the hill
  // goes on rising at least as steeply past ring 7.
  const float r[] = {13.75f, 14.77f, 15.95f, 17.43f, 19.8f};
  const float z[] = {1.61f, 1.95f, 2.33f, 2.78f, 3.38f};
  const auto hill_behind_bush = [&](float level2_h, bool levels_off) {
    Scan s;
    add(s, 0, 0, 8.54f, 0.28f, 1);
    for (int ring = 1; ring <= 6; ++ring) {
      add(s, ring, 0, 8.85f, 0.28f + 0.2f * static_cast<float>(ring), 2);
    }
    for (int k = 0; k < 5; ++k) {
      // levels_off: a roof or a fence top past ring 7, level with it (no hill)
      add(s, 7 + k, 0, r[k], levels_off && k > 0 ? z[0] : z[k], 1);
    }
    std::vector<float> level2(s.cloud.size(), 0.f);
    level2[7] = level2_h;
    return label(s, level2).ground;
  };
  CHECK(hill_behind_bush(0.f, false) ==
        std::vector<std::uint8_t>{1, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1});
  // Where the level-2 surface lies 0.5 m under ring 7, or the surface past it stops bending
  // up, ring 7 is something standing there, as before.
  CHECK(hill_behind_bush(0.5f, false)[7] == 0);
  CHECK(hill_behind_bush(0.f, true)[7] == 0);
}

TEST_CASE("column profiles: a far wall's foot past a near wall needs level 2 on the start's guess",
          "[detector][profiles]") {
  // A ramp's parapet 4.3 m out hides rings 0-1 (sim garage, seed 2); rings 2-4 meet a wall
  // 15.3 m out, ring 2 by chance level with the start under the sensor (z 0.02, within the
  // steep band of a profile that has not met the ground yet). The level-2 surface lies
  // 0.7 m under it there: the start's level says nothing 15 m past a wall.
  const auto far_foot = [](float level2_h) {
    Scan s;
    add(s, 0, 0, 4.3f, 1.24f, 2);
    add(s, 1, 0, 4.3f, 1.34f, 2);
    for (int ring = 2; ring <= 4; ++ring) {
      add(s, ring, 0, 15.3f, 0.02f + 0.36f * static_cast<float>(ring - 2), 2);
    }
    std::vector<float> level2(s.cloud.size(), 0.f);
    level2[2] = level2_h;
    return label(s, level2).ground[2];
  };
  CHECK(far_foot(0.7f) == 0);
  CHECK(far_foot(0.f) == 1);  // where level 2 agrees, the band stands
}

TEST_CASE("column profiles: ground met by a rising ray rises more steeply than the ray",
          "[detector][profiles]") {
  // Inside a ramp (sim garage, seed 2, Puck Hi-Res): the parapet 4.3 m out is the column's
  // first return (rings 0-5); rings 6-8 rise over the sensor (1.8 m) and meet the street
  // 21-71 m out, 2.7-7.8 m up in the vehicle frame (the vehicle is pitched down the ramp).
  // Level 2 follows the ramp, 1.5 m under the street. Each ring rises from the one before at
  // 0.1, more steeply than ring 6's ray (0.043): a surface met from above, ground. A roof
  // levels off past its first return. One rising return is enough only where the column
  // ends there (its higher rings went to the sky) and only the parapet stood in front (sim
  // garage_s203 at 5 Hz); a return past a car that climbs to a facade is not (jam_s3).
  const auto street_over_parapet = [](float z7, bool ring8, bool car = false) {
    Scan s;
    for (int ring = 0; ring <= (car ? 4 : 5); ++ring) {
      add(s, ring, 0, 4.3f, 1.24f + 0.1f * static_cast<float>(ring), 2);
    }
    if (car) add(s, 5, 0, 15.f, 1.f, 2);  // refused, not on a face
    add(s, 6, 0, 21.2f, 2.72f, 1);
    add(s, 7, 0, 32.6f, z7, 1);
    if (ring8) add(s, 8, 0, 71.3f, 7.8f, 1);
    return label(s, std::vector<float>(s.cloud.size(), 1.5f)).ground[6];
  };
  CHECK(street_over_parapet(3.87f, true) == 1);
  CHECK(street_over_parapet(2.9f, true) == 0);   // levels off: met from below
  CHECK(street_over_parapet(3.87f, false) == 1);  // one rising return, then the sky
  CHECK(street_over_parapet(3.87f, false, true) == 0);  // ... past a refused return
  CHECK(street_over_parapet(3.87f, true, true) == 1);   // two rising returns are enough
}

TEST_CASE("column profiles: a shoulder under an overhang is the underside of an object",
          "[detector][profiles]") {
  // Sim bank_s1: rings 0-3 climb a bank face at 0.35; ring 4 meets, 8 m past ring 3, a
  // tree crown on the bank's top under the profile extrapolated up the face, still rising
  // from ring 3 (a hill's shoulder, rule 1); ring 5 meets the crown 2.5 m nearer and higher:
  // met from below, so ring 4's return is no ground. The level-2 surface follows the face.
  enum Above { kSky, kCrownNearer, kCrownNearerLower, kFarther };
  const auto ring4 = [](Above above) {
    Scan s;
    const float r[] = {10.f, 11.4f, 12.4f, 13.4f, 21.5f};
    const float z[] = {0.f, 0.35f, 0.7f, 1.05f, 3.f};
    for (int ring = 0; ring < 5; ++ring) add(s, ring, 0, r[ring], z[ring], ring < 4 ? 1 : 2);
    if (above == kCrownNearer) add(s, 5, 0, 19.f, 3.6f, 2);
    if (above == kCrownNearerLower) add(s, 5, 0, 19.f, 2.95f, 2);
    if (above == kFarther) add(s, 5, 0, 30.f, 5.f, 1);
    return label(s, std::vector<float>(s.cloud.size(), 0.f)).ground[4];
  };
  CHECK(ring4(kSky) == 1);  // nothing says the shoulder is not the top's ground
  CHECK(ring4(kFarther) == 1);
  CHECK(ring4(kCrownNearer) == 0);
  // Sim bank_s102: the crown's return lower than ring 4's but over ring 4's ray at 19 m
  // (2.86 m from the sensor at 1.8 m): ring 4 passed on under it, so it is no ground there.
  CHECK(ring4(kCrownNearerLower) == 0);
}

TEST_CASE("column profiles: the last return far past a climb over the sensor stands on its top",
          "[detector][profiles]") {
  // Sim bank_s1 / bank_s101: the rings climb a bank face at 0.35 to over the sensor (1.8 m);
  // the bank's top levels off, hidden from every rising ray past its edge, and the next ring
  // meets a shed on it, nearly twice as far as the last face return, with nothing over it.
  // The profile extrapolated up the face runs far over that return, which still rises from
  // the face (a hill's shoulder, rule 1, would take it).
  enum Next { kNothing, kHigherRing };
  // Returns the label of the return at (r, z) after `face_rings` returns on the face.
  const auto after_face = [](int face_rings, float r, float z, Next next) {
    Scan s;
    const float face_r[] = {10.f, 11.5f, 13.f, 14.5f, 16.f};
    for (int ring = 0; ring < face_rings; ++ring) {
      add(s, ring, 0, face_r[ring], 0.35f * (face_r[ring] - 8.f), 1);
    }
    add(s, face_rings, 0, r, z, 2);
    if (next == kHigherRing) add(s, face_rings + 1, 0, r + 15.f, z + 3.f, 1);  // rising on
    const Labels out = label(s, std::vector<float>(s.cloud.size(), 0.f));
    return out.ground[static_cast<std::size_t>(face_rings)];
  };
  // The face's last return at 16 m, 2.8 m up: over the sensor.
  CHECK(after_face(5, 30.f, 5.f, kNothing) == 0);
  // A higher ring of the column met something farther: the climb's surface may rise on.
  CHECK(after_face(5, 30.f, 5.f, kHigherRing) == 1);
  // Within 1.4 times the face's last return's distance: the face may be bending over.
  CHECK(after_face(5, 22.f, 4.f, kNothing) == 1);
  // 1.5 times as far (sim bank_s1001: objects on the bank's top 1.42 times as far).
  CHECK(after_face(5, 24.f, 4.f, kNothing) == 0);
  // The face's last return at 13 m, 1.75 m up: under the sensor, where a top is seen by
  // falling rays.
  CHECK(after_face(3, 25.f, 3.5f, kNothing) == 1);
  // Sim bank_s2804: rising only 0.03 from the face's last return (less than a shoulder: a
  // lower surface for the walk), 2.5 times as far. The face levelled off (0.35 -> 0.03),
  // and what the next ring met stands on its top.
  CHECK(after_face(5, 40.f, 3.6f, kNothing) == 0);
  CHECK(after_face(5, 40.f, 2.7f, kNothing) == 1);  // under the face's last return
  // A hillside climbing over the sensor to 36 m, the next ring 80 m out rising gently from
  // it: where the gradient falls by 0.12 only, the hillside may rise on less steeply (sim
  // hills_s605: 0.11 to 0.07); by 0.27, it levelled off as the face did.
  const auto hillside = [](float gradient, float last_step) {
    Scan h;
    const float r[] = {6.f, 9.f, 13.f, 18.f, 24.f, 30.f, 36.f, 80.f};
    for (int ring = 0; ring < 7; ++ring) add(h, ring, 0, r[ring], gradient * (r[ring] - 6.f), 1);
    add(h, 7, 0, r[7], gradient * 30.f + last_step * 44.f, 1);
    return label(h, std::vector<float>(h.cloud.size(), 0.f)).ground[7];
  };
  CHECK(hillside(0.15f, 0.03f) == 1);
  CHECK(hillside(0.3f, 0.03f) == 0);

  // Sim garage_s2: from inside a ramp, rings 0-2 meet its wall 5 m out, ring 3 the street
  // over it at 3.4 m and ring 4 ground far beyond, nothing over it: the climb is one return
  // resumed past an obstacle, no face that levelled off.
  Scan s;
  for (int ring = 0; ring < 3; ++ring) {
    add(s, ring, 0, 5.f, 0.6f + 0.5f * static_cast<float>(ring), 2);
  }
  add(s, 3, 0, 26.4f, 3.4f, 1);
  add(s, 4, 0, 76.f, 8.7f, 1);
  const Labels street = label(s, std::vector<float>(s.cloud.size(), 0.f));
  CHECK(street.ground[3] == 1);
  CHECK(street.ground[4] == 1);
}

TEST_CASE("column profiles: a return bending off a steep face under an overhang is no ground",
          "[detector][profiles]") {
  // Sim bank_s102 (frame 1): rings 0-4 climb a bank face steepening to 0.5; ring 5 lands
  // 17 m past ring 4, still rising from it (0.14) but bending off the face by more than a
  // shoulder may, so the walk takes it as a level surface beyond the face; ring 6 met a tree
  // crown 3 m nearer and over ring 5's ray there: ring 5 passed on under the crown into it.
  // The level-2 surface follows the face.
  const auto ring5 = [](bool crown) {
    Scan s;
    const float r[] = {8.f, 9.f, 10.f, 11.f, 12.f, 29.f};
    const float z[] = {0.f, 0.2f, 0.6f, 1.1f, 1.6f, 1.6f + 0.14f * 17.f};
    for (int ring = 0; ring < 6; ++ring) add(s, ring, 0, r[ring], z[ring], ring < 5 ? 1 : 2);
    add(s, 6, 0, crown ? 26.f : 40.f, crown ? 4.3f : 6.f, 2);
    return label(s, std::vector<float>(s.cloud.size(), 0.f)).ground[5];
  };
  CHECK(ring5(false) == 1);  // nothing says the terrain did not rise on to meet the ray
  CHECK(ring5(true) == 0);
}

TEST_CASE("column profiles: a kink the next return falls under, onto no lower surface, was an object",
          "[detector][profiles]") {
  // Sim fences_s102: rings 0-2 on the road, ring 3 on a fence line 0.34 m up 2.3 m past
  // ring 2 (it bends the profile up: a kink), ring 4 on a second fence 24.4 m out, far under
  // the profile the kink extrapolated (a lower surface, rule 1), ring 5 on a third. The
  // level-2 surface, at z = 0 with ground of its own, lies 0.6 m under ring 4: no lower
  // surface there, so the kink was the fence, and the walk goes on past it from the road.
  // `ring4_level2`: ring 4's height over the level-2 surface; `measured4`: whether that
  // surface has ground of its own under ring 4.
  const auto labels = [](float ring4_level2, bool measured4) {
    Scan s;
    add(s, 0, 0, 9.5f, 0.f, 1);
    add(s, 1, 0, 11.7f, 0.f, 1);
    add(s, 2, 0, 15.2f, 0.f, 1);
    add(s, 3, 0, 17.5f, 0.34f, 2);
    add(s, 4, 0, 24.4f, 0.61f, 2);
    add(s, 5, 0, 34.7f, 1.30f, 2);
    std::vector<float> level2 = s.cloud.z;
    level2[3] = 0.f;  // the cells climbed onto the first fence line
    level2[4] = ring4_level2;
    level2[5] = ring4_level2 + 0.69f;
    std::vector<bool> measured(s.cloud.size(), true);
    measured[4] = measured4;
    const Labels out = label_by_cell(s, level2, {}, measured);
    return std::vector<int>(out.ground.begin(), out.ground.end());
  };
  CHECK(labels(0.61f, true) == std::vector<int>{1, 1, 1, 0, 0, 0});
  // The level-2 surface follows ring 4 (a field below a bank's edge), or has no ground of
  // its own there: ring 4 may be the lower surface, and the kink stays ground.
  CHECK(labels(0.1f, true)[3] == 1);
  CHECK(labels(0.61f, false)[3] == 1);

  // Sim garage_s2: the kink is the column's first ground (the street over a ramp's wall,
  // 1.2 m up 9.5 m out), with only the start's guess before it to go back to: it stays.
  Scan s;
  add(s, 0, 0, 9.5f, 1.2f, 1);
  add(s, 1, 0, 20.f, 1.3f, 1);
  std::vector<float> level2 = {0.f, 1.3f};  // the cells follow the kink, not ring 1
  CHECK(label(s, level2, {}, true).ground[0] == 1);
}

TEST_CASE("column profiles: a kink the ground runs on under, past it, was an object",
          "[detector][profiles]") {
  // Sim fences_s203_tilt frame 2, column 840: rings 0-1 on the field, ring 2 on a fence
  // 0.9 m past ring 1 and 0.26 m up (it bends the profile up: a kink), ring 3 over or
  // through the fence onto the field 26.6 m out, far under the profile the kink
  // extrapolated, level with the field before the kink, on a level-2 surface with ground of
  // its own. The field ran on under the kink: the kink was the fence.
  // `kink_z`, `past_z`: heights of ring 2 and ring 3; `measured`: whether the level-2 surface
  // has ground of its own under ring 3. Returns ring 2's label.
  const auto kink = [](float kink_z, float past_z, bool measured) {
    Scan s;
    add(s, 0, 0, 9.7f, 0.f, 1);
    add(s, 1, 0, 12.2f, 0.f, 1);
    add(s, 2, 0, 13.1f, kink_z, 2);
    add(s, 3, 0, 26.6f, past_z, 1);
    std::vector<bool> has_ground(s.cloud.size(), true);
    has_ground[3] = measured;
    std::vector<float> level2 = s.cloud.z;  // heights over a level-2 surface at z = 0 ...
    level2[2] = 0.f;                        // ... which climbed onto the fence line
    return label_by_cell(s, level2, {}, has_ground).ground[2];
  };
  CHECK(kink(0.26f, -0.05f, true) == 0);
  // No ground of its own under ring 3 (the cells only extrapolate there, as past a valley's
  // near side): ring 3 may be a lower surface, and the kink stays ground.
  CHECK(kink(0.26f, -0.05f, false) == 1);
  // Sim urban_s4_hires, a kerb: ring 0 on the road 10.7 m out, ring 1 on the pavement 0.5 m
  // farther and 0.18 m up (a kink), ring 2 on the pavement 13.1 m out, more than drop_m
  // under the profile the kink extrapolated, 0.19 m over the road extrapolated but level
  // with the kink: the pavement, not ground running on under an object.
  const Scan kerb = ground_column({10.7f, 11.2f, 13.1f, 15.8f}, {-0.1f, 0.08f, 0.09f, 0.12f});
  CHECK(label(kerb, std::vector<float>(4, 0.f), {}, true).ground ==
        std::vector<std::uint8_t>(4, 1));
  // Real vlp16_county_fair frame 1, 157 degrees (heights from the ground under the sensor):
  // a climb at 0.05, ring 5 kinking up 0.25 m over 1.3 m, ring 6 8 m on, level with ring 5
  // but 0.19 m under the climb extrapolated: a plateau, nearer to the kink's height.
  const Scan plateau = ground_column({5.58f, 6.3f, 7.28f, 8.55f, 10.32f, 11.59f, 19.53f},
                                     {0.f, 0.03f, 0.07f, 0.13f, 0.22f, 0.47f, 0.46f});
  CHECK(label(plateau, std::vector<float>(7, 0.f), {}, true).ground ==
        std::vector<std::uint8_t>(7, 1));
}

TEST_CASE("column profiles: past a face, ground that runs on along a measured level 2 resumes",
          "[detector][profiles]") {
  // Sim garage_s5405_tilt frame 1, column 293: the vehicle down a garage ramp, rings 0-5 on
  // the ramp's retaining wall 4.3-4.4 m out (a face), rings 6 and 7 over it on the street
  // 13.8 and 19.8 m out, 1.34 and 1.76 m up, rising 0.07-0.1 on the tilted mount, where the
  // level-2 surface has ground of its own; ring 8 on the street 34.8 m out, where level 2
  // only extrapolates. The street runs on from ring 6 at the chord's gradient: it resumes.
  // `min_m`: resume_on_level2_min_m; `measured6`, `measured7`: whether level 2 has ground of
  // its own under ring 6 and ring 7. Returns the labels of rings 6 and 7 (ring 8, the column
  // alone, is left to the checks after the walk).
  const auto street = [](float min_m, bool measured6, bool measured7) {
    Scan s;
    const float wall_z[] = {0.84f, 0.98f, 1.14f, 1.3f, 1.45f, 1.6f};
    for (int ring = 0; ring < 6; ++ring) add(s, ring, 0, 4.35f, wall_z[ring], 2);
    add(s, 6, 0, 13.8f, 1.34f, 1);
    add(s, 7, 0, 19.8f, 1.76f, 1);
    add(s, 8, 0, 34.8f, 2.83f, 1);
    std::vector<float> level2 = s.cloud.z;  // over a level-2 surface at z = 0 ...
    level2[6] = level2[7] = 0.f;            // ... fitted to the street under rings 6 and 7
    std::vector<bool> measured(s.cloud.size(), true);
    measured[6] = measured6;
    measured[7] = measured7;
    measured[8] = false;
    ProfileParams p;
    p.resume_on_level2_min_m = min_m;
    const auto ground = label_by_cell(s, level2, {}, measured, nullptr, false, p).ground;
    return std::vector<std::uint8_t>(ground.begin() + 6, ground.begin() + 8);
  };
  const float min_m = ProfileParams{}.resume_on_level2_min_m;
  CHECK(street(min_m, true, true) == std::vector<std::uint8_t>{1, 1});
  CHECK(street(1000.f, true, true) == std::vector<std::uint8_t>{0, 0});  // the rule off
  // Where level 2 only extrapolates under either return, nothing vouches for the street.
  CHECK(street(min_m, false, true) == std::vector<std::uint8_t>{0, 0});
  CHECK(street(min_m, true, false) == std::vector<std::uint8_t>{0, 0});
  // Sim fences_s4805_dual frame 4, column 450: rings 0-1 on a fence 5.2 m out, ring 2 on
  // its top 6.0 m out, 0.66 m up, and ring 3 0.8 m behind it on the top, both on a level-2
  // surface fitted to that top; ring 4 on the field 13 m out. The top runs on for 0.8 m
  // only: no ground.
  Scan fence;
  const float fr[] = {5.2f, 5.2f, 6.0f, 6.8f, 13.f}, fz[] = {0.44f, 0.62f, 0.66f, 0.74f, 0.22f};
  for (int ring = 0; ring < 5; ++ring) add(fence, ring, 0, fr[ring], fz[ring], ring < 4 ? 2 : 1);
  const std::vector<float> fence_level2 = {0.44f, 0.62f, 0.03f, 0.02f, -0.01f};
  const std::vector<bool> all(5, true);
  CHECK(label_by_cell(fence, fence_level2, {}, all).ground[2] == 0);
  ProfileParams near;
  near.resume_on_level2_min_m = 0.3f;
  CHECK(label_by_cell(fence, fence_level2, {}, all, nullptr, false, near).ground[2] == 1);
  // Sim fences_s301_tilt frame 4, column 430: ring 0 on the field, rings 1-4 on a fence
  // 6.5-7.1 m out, ring 5 past it on a second fence's top 12.5 m out, 0.47 m up, where level
  // 2 was fitted to it; ring 6 on the field 25.9 m out, on level 2 too, but falling from
  // ring 5 (-0.03) where the chord to it rose 0.07: no ground running on.
  Scan second;
  const float sr[] = {6.2f, 6.5f, 6.6f, 6.6f, 7.1f, 12.5f, 25.9f};
  const float sz[] = {-0.01f, 0.12f, 0.37f, 0.61f, 0.77f, 0.47f, 0.02f};
  for (int ring = 0; ring < 7; ++ring) {
    add(second, ring, 0, sr[ring], sz[ring], ring == 0 || ring == 6 ? 1 : 2);
  }
  std::vector<float> second_level2 = second.cloud.z;
  second_level2[5] = 0.01f;
  second_level2[6] = -0.04f;
  CHECK(label_by_cell(second, second_level2, {}, std::vector<bool>(7, true)).ground[5] == 0);
}

TEST_CASE(
    "column profiles: past a face, ground in one straight line over a measured level 2 resumes",
    "[detector][profiles]") {
  // Sim garage_s501_hires frame 4, column 262: the vehicle down a garage ramp, rings 0-6 on
  // the ramp's retaining wall 4 m out (a face up to 1.64 m), rings 7-9 over it on the street
  // 17.8, 25.5 and 45.2 m out, 1.57, 2.08 and 3.36 m up, rising 0.066 and 0.065 on the
  // pitched vehicle. Level 2 follows the ramp at z = 0: it has ground of its own under ring 7,
  // none under rings 8 and 9. `ring9_z`: ring 9's height; `p`: the parameters. Returns the
  // labels of rings 7-9.
  const auto street = [](float ring9_z, const ProfileParams& p, float ring8_r = 25.5f,
                         float ring9_r = 45.2f) {
    Scan s;
    const float wall_z[] = {1.09f, 1.19f, 1.28f, 1.37f, 1.46f, 1.55f, 1.64f};
    for (int ring = 0; ring < 7; ++ring) add(s, ring, 0, 4.f, wall_z[ring], 2);
    add(s, 7, 0, 17.8f, 1.57f, 1);
    add(s, 8, 0, ring8_r, 1.57f + 0.066f * (ring8_r - 17.8f), 1);
    add(s, 9, 0, ring9_r, ring9_z, 1);
    std::vector<bool> measured(s.cloud.size(), true);
    measured[8] = measured[9] = false;
    const auto ground = label_by_cell(s, s.cloud.z, {}, measured, nullptr, false, p).ground;
    return std::vector<std::uint8_t>(ground.begin() + 7, ground.end());
  };
  const ProfileParams defaults;
  CHECK(street(3.36f, defaults) == std::vector<std::uint8_t>{1, 1, 1});
  ProfileParams off;
  off.in_line_span_m = 1000.f;
  CHECK(street(3.36f, off) == std::vector<std::uint8_t>{0, 0, 0});  // the rule off
  // Ring 9 off the line (rising 0.09 from ring 8): no surface vouches for ring 7.
  CHECK(street(3.9f, defaults) == std::vector<std::uint8_t>{0, 0, 0});
  // In line over less than in_line_span_m (ring 9 24.8 m out): too short to tell.
  CHECK(street(1.57f + 0.066f * 7.f, defaults, 20.8f, 24.8f) == std::vector<std::uint8_t>{0, 0, 0});
  // Sim jam_s604_strongest frame 0, column 471: rings 0-5 on a car's side 5.7 m out (up to
  // 1.44 m), then obstacle returns 18.4, 27 and 51 m out, 0.97, 1.46 and 2.82 m up, in line
  // by chance (0.057 both), and 90 m out 6.65 m up, over a measured road. Under the car
  // side's top, rings 6 and 7 would be level ground running on under the sensor: there the
  // line does not count.
  Scan jam;
  const float side_z[] = {0.42f, 0.63f, 0.83f, 1.04f, 1.24f, 1.44f};
  for (int ring = 0; ring < 6; ++ring) add(jam, ring, 0, 5.7f, side_z[ring], 2);
  const float jr[] = {18.4f, 27.f, 51.f, 90.f}, jz[] = {0.97f, 1.46f, 2.82f, 6.65f};
  for (int n = 0; n < 4; ++n) add(jam, 6 + n, 0, jr[n], jz[n], 2);
  const auto jam_ground = label_by_cell(jam, jam.cloud.z, {}, std::vector<bool>(10, true)).ground;
  CHECK(std::vector<std::uint8_t>(jam_ground.begin() + 6, jam_ground.begin() + 8) ==
        std::vector<std::uint8_t>{0, 0});
}

TEST_CASE("column profiles: the column's first return at a foot may lie a little under the start",
          "[detector][profiles]") {
  // Sim embankment_s4803 frame 4: ring 0 on the crowned road's edge 7.15 m out, 0.07 m
  // under the vehicle's ground, at the foot of a low object that ring 1 meets 7.2 m out,
  // 0.19 m up (a steep pair), ring 2 on the fields 25.7 m out. The first return lies on the
  // level-2 surface: the road, though outside the 0.06 m band of a steep return.
  // `ring0_z`, `ring0_level2`: ring 0's height and its height over the level-2 surface.
  const auto ring0 = [](float ring0_z, float ring0_level2) {
    Scan s;
    add(s, 0, 0, 7.15f, ring0_z, 1);
    add(s, 1, 0, 7.2f, 0.19f, 2);
    add(s, 2, 0, 25.7f, -2.22f, 1);
    std::vector<float> level2 = {ring0_level2, 0.38f, 0.f};
    return label(s, level2, {}, true).ground[0];
  };
  CHECK(ring0(-0.07f, -0.01f) == 1);
  CHECK(ring0(-0.12f, -0.01f) == 0);  // more than 0.1 m under: a face on a lower surface
  CHECK(ring0(-0.07f, 0.2f) == 0);    // the level-2 surface under it disagrees
}

TEST_CASE("column profiles: a kink level with the ground before it ends a descent, no object",
          "[detector][profiles]") {
  // Sim embankment_s4804_dual frame 2: ring 0 on a box's face 0.31 m up 5.7 m out, taken as
  // the column's first ground; ring 1 on the road 7.0 m out (0.34 m under it: the profile
  // now falls at 0.25); ring 2 on the road 8.1 m out, level with ring 1 (a kink from that
  // fall); ring 3 on the embankment's side 27.5 m out, 1.05 m over the level-2 surface of
  // the fields. Ring 2 did not rise from ring 1: the road, not an object to take back.
  // `ring2_z`: ring 2's height (0.3 m up: a low object on the road, taken back).
  const auto ring2 = [](float ring2_z) {
    Scan s;
    add(s, 0, 0, 5.71f, 0.31f, 2);
    add(s, 1, 0, 6.99f, -0.03f, 1);
    add(s, 2, 0, 8.06f, ring2_z, 1);
    add(s, 3, 0, 27.53f, -1.54f, 1);
    std::vector<float> level2 = s.cloud.z;
    level2[3] = 1.05f;
    return label(s, level2, {}, true).ground[2];
  };
  CHECK(ring2(-0.02f) == 1);
  CHECK(ring2(0.3f) == 0);
}

TEST_CASE("column profiles: a shoulder level with a roof the rings over it met from below is none",
          "[detector][profiles]") {
  // Sim bank_s302: rings 0-11 climb a bank face at about 0.4; ring 12 meets, 14 m past
  // ring 11, the far edge of a roof 2.4 m over the bank's top: under the profile
  // extrapolated up the face and still rising from ring 11 (a hill's shoulder, rule 1).
  // Ring 13 passes on over the roof, farther; rings 14 and 15 meet its underside nearer,
  // over ring 12's ray and level with ring 12: ring 12 is that roof, not the top's ground.
  const auto ring12 = [](float roof_z, bool roof_seen) {
    Scan s;
    const float r[] = {7.4f, 7.8f, 8.3f, 8.9f, 9.4f, 10.1f, 10.9f, 11.8f, 12.9f, 14.1f, 15.6f, 17.6f};
    const float z[] = {-0.1f, 0.08f, 0.27f, 0.48f, 0.72f, 0.99f, 1.31f, 1.67f, 2.1f, 2.61f, 3.24f, 4.03f};
    for (int ring = 0; ring < 12; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
    add(s, 12, 0, 31.6f, 6.87f, 2);
    add(s, 13, 0, 38.4f, 9.33f, 2);
    if (roof_seen) {
      add(s, 14, 0, 21.7f, roof_z, 2);
      add(s, 15, 0, 18.9f, roof_z + 0.06f, 2);
    }
    return label(s, std::vector<float>(s.cloud.size(), 0.f)).ground[12];
  };
  CHECK(ring12(6.87f, false) == 1);  // nothing says the shoulder is not the top's ground
  CHECK(ring12(6.87f, true) == 0);
  // A canopy well over ring 12 (a tree crown 1.1 m higher): ground may lie under it.
  CHECK(ring12(8.f, true) == 1);
}

TEST_CASE("column profiles: past a face, a return level with an underside nearer over it is none",
          "[detector][profiles]") {
  // Sim bank_s5603_5hz frame 3, column 2720: rings 0-8 climb a bank at about 0.39 to 11.7 m;
  // rings 9-11 meet a face 10.6 m out (2.5-3.24 m up). Past it ring 12 meets, 18 m out and
  // 4.79 m up, the far edge of a tree crown's underside 2.55 m over the bank's top, on the
  // bank's slope extrapolated from ring 8 (0.42). Ring 13 meets that underside 14.7 m out,
  // level with ring 12, over its ray; rings 14 and 15 a face of the crown 14.1 m out.
  // `ring13_r`, `ring13_z`: ring 13's return; `face_under_13`: ring 11 meets a face under
  // ring 13 instead of the near one; `face`: rings 9-11 meet that face, else the bank going on
  // at 0.39. Returns ring 12's label.
  const auto ring12 = [](float ring13_r, float ring13_z, bool face_under_13, bool face,
                         const ProfileParams& p) {
    Scan s;
    const float r[] = {6.6f, 7.0f, 7.5f, 7.9f, 8.5f, 9.2f, 9.9f, 10.7f, 11.7f};
    const float z[] = {0.19f, 0.34f, 0.5f, 0.7f, 0.91f, 1.15f, 1.43f, 1.76f, 2.15f};
    for (int ring = 0; ring < 9; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
    if (face) {
      add(s, 9, 0, 10.6f, 2.5f, 2);
      add(s, 10, 0, 10.6f, 2.87f, 2);
      add(s, 11, 0, face_under_13 ? ring13_r : 10.6f, face_under_13 ? 4.3f : 3.24f, 2);
    } else {
      int ring = 9;
      for (const float bank_r : {12.8f, 14.1f, 15.7f})
        add(s, ring++, 0, bank_r, 2.15f + 0.39f * (bank_r - 11.7f), 1);
    }
    add(s, 12, 0, 18.f, 4.79f, 2);
    add(s, 13, 0, ring13_r, ring13_z, 2);
    add(s, 14, 0, 14.1f, 5.19f, 2);
    add(s, 15, 0, 14.1f, 5.71f, 2);
    return label_by_cell(s, s.cloud.z, {}, std::vector<bool>(s.cloud.size(), false), nullptr, false,
                         p)
        .ground[12];
  };
  const ProfileParams defaults;
  CHECK(ring12(14.7f, 4.79f, false, true, defaults) == 0);
  ProfileParams off;
  off.underside_level_m = 0.f;
  CHECK(ring12(14.7f, 4.79f, false, true, off) == 1);  // the rule off
  // Ring 13 0.15 m higher: no underside level with ring 12 (a crown over ground past it).
  CHECK(ring12(14.7f, 4.94f, false, true, defaults) == 1);
  // Ring 13 more than underside_reach_m nearer: too far from ring 12 to be one underside.
  CHECK(ring12(12.9f, 4.79f, false, true, defaults) == 1);
  // A lower ring met a face under ring 13: a face's side, not an underside.
  CHECK(ring12(14.7f, 4.79f, true, true, defaults) == 1);
  // Not past an obstacle: ring 12 goes on from the bank's ground, which runs on under it.
  CHECK(ring12(14.7f, 4.79f, false, false, defaults) == 1);
}

TEST_CASE("column profiles: the street over a ramp's wall, past its top or from under the sensor",
          "[detector][profiles]") {
  // Deep in a ramp (sim garage_s501, Puck Hi-Res, frame 4): rings 0-6 meet the retaining
  // wall 3.7-3.9 m out; the rings over it meet the street 1.5-3.8 m up in the vehicle frame
  // (pitched down the ramp). Level 2 follows the ramp: the street stands over it by its z.
  const auto heights_over_ramp = [](const Scan& s) { return s.cloud.z; };
  const auto wall = [](Scan& s, float r, int top_ring) {
    for (int ring = 0; ring <= top_ring; ++ring) {
      add(s, ring, 0, r, 1.1f + 0.09f * static_cast<float>(ring), 2);
    }
  };
  // Column 1540: ring 7 grazes the wall's top 0.3 m behind its face; ring 8 meets the street
  // over the sensor and ring 9 farther up (one rising return, then the sky): the wall's top
  // is part of that face, so only faces stood in front.
  const auto past_wall_top = [&](float top_r) {
    Scan s;
    wall(s, 3.93f, 6);
    add(s, 7, 0, top_r, 1.73f, 2);
    add(s, 8, 0, 25.48f, 2.08f, 1);
    add(s, 9, 0, 46.f, 3.38f, 1);
    return label(s, heights_over_ramp(s)).ground[8];
  };
  CHECK(past_wall_top(4.23f) == 1);
  CHECK(past_wall_top(5.f) == 0);  // a refused return 1 m behind the face is no wall top
  // Column 1520: ring 7 meets the street under the sensor (1.56 m at 19 m); ring 8 goes on
  // rising to over the sensor, where it rises over its ray to ring 9.
  const auto street_from_under = [&](float z9, bool measured, bool overhang) {
    Scan s;
    wall(s, 3.74f, 6);
    add(s, 7, 0, 19.08f, 1.56f, 1);
    add(s, 8, 0, 28.85f, 2.12f, 1);
    add(s, 9, 0, 58.38f, z9, 1);
    if (overhang) add(s, 10, 0, 19.f, 2.5f, 2);  // nearer than ring 8, over its ray
    return label(s, heights_over_ramp(s), {}, measured).ground[7];
  };
  CHECK(street_from_under(3.82f, false, false) == 1);
  // Not a car's roof seen over a van's side where level 2 measured the road under it (ring
  // 9 bending up 0.023 from the line of rings 7 and 8: in line, it is the street whatever
  // level 2 says, runs_on_in_line), nor one with a truck's box or a facade beyond (the
  // surface bends up by more than gradient_step at ring 8, or something nearer overhangs
  // ring 8: jam).
  CHECK(street_from_under(4.5f, false, false) == 1);
  CHECK(street_from_under(4.5f, true, false) == 0);
  CHECK(street_from_under(3.82f, true, false) == 1);
  CHECK(street_from_under(14.f, false, false) == 0);
  CHECK(street_from_under(3.82f, false, true) == 0);
}

TEST_CASE("column profiles: the street over a ramp's wall running on under the sensor",
          "[detector][profiles]") {
  // Sim garage_s703 tilted (pitch 3, roll 4 degrees), frame 1, heights 0.2 m lower (sensor
  // 1.8 m here, 2.0 m there): the vehicle pitched on the ramp sees the street beside it
  // rise gently but never climb over the sensor. Level 2 follows the ramp: the street
  // stands over it by its z. The retaining wall's face: rings 0..top_ring, `top_z` the
  // highest return. Each column is repeated over `columns` columns (1 degree apart), so
  // that its rings run along the street for a ring run's length.
  struct Return {
    int ring;
    float r, z;
  };
  const auto scan = [](const std::vector<Return>& column, int columns) {
    Scan s;
    for (int ring = 0; ring < kRings; ++ring) {  // cloud order: ring, column
      for (const Return& ret : column) {
        if (ret.ring != ring) continue;
        for (int col = 0; col < columns; ++col) add(s, ring, col, ret.r, ret.z, 1);
      }
    }
    return s;
  };
  const auto wall = [](std::vector<Return>& column, float r, int top_ring, float top_z) {
    for (int ring = 0; ring <= top_ring; ++ring) {
      column.push_back({ring, r, top_z - 0.13f * static_cast<float>(top_ring - ring)});
    }
  };
  // Ground of return `ring` in the middle column.
  const auto street = [&](const std::vector<Return>& column, int ring, int columns = 30,
                          bool on_plane = false) {
    const Scan s = scan(column, columns);
    // on_plane: a level-1 plane explains the street's cells (none the wall's)
    std::vector<float> plane(s.cloud.size(), std::nanf(""));
    for (std::size_t i = 0; i < s.cloud.size(); ++i) {
      if (on_plane && s.cloud.range_xy[i] > 10.f) plane[i] = 0.f;
    }
    const Labels l = label(s, s.cloud.z, plane);
    for (std::size_t i = 0; i < s.cloud.size(); ++i) {
      if (s.cloud.ring[i] == ring && s.cloud.column[i] == columns / 2) return l.ground[i];
    }
    return std::uint8_t{9};
  };
  // Column 1440: rings 5 and 6 on the street, under the sensor, ring 6 the column's last.
  // Each ring rises from the one before by `gradient`.
  const auto to_column_end = [&](float top_z, float r6, float gradient, int columns = 30,
                                 bool on_plane = false) {
    std::vector<Return> column;
    wall(column, 3.85f, 4, top_z);
    column.push_back({5, 19.6f, 1.1f});
    column.push_back({6, r6, 1.1f + gradient * (r6 - 19.6f)});
    return street(column, 5, columns, on_plane);
  };
  CHECK(to_column_end(1.53f, 38.43f, 0.0356f) == 1);
  CHECK(to_column_end(1.53f, 25.f, 0.03f) == 1);
  // Not a roof past a car's side, level with the side's highest return or over it
  // (jam_s604), nor roofs rising from one to the next by level_run_gradient or more
  // (jam_s704: 0.07-0.08), nor level roofs short along their ring (7 columns: 2.4 m at
  // 19.6 m; jam_s1003 at Hi-Res).
  CHECK(to_column_end(1.05f, 38.43f, 0.0356f) == 0);
  CHECK(to_column_end(1.53f, 25.f, 0.07f) == 0);
  CHECK(to_column_end(1.53f, 38.43f, 0.0356f, 7) == 0);
  // A return a level-1 plane explains past an obstacle stays ground, short run or not: the
  // plane takes it before the level run is tried (garage_s4 lost 0.005-0.007 F1 otherwise).
  CHECK(to_column_end(1.53f, 38.43f, 0.0356f, 7, true) == 1);
  // Column 1480: ring 6 on the street under the sensor, ring 7 the column's last return,
  // over the sensor (no return beyond it to rise over its ray).
  const auto to_last_over_sensor = [&](float top_z) {
    std::vector<Return> column;
    wall(column, 4.06f, 5, top_z);
    column.push_back({6, 22.33f, 1.55f});
    column.push_back({7, 50.69f, 3.0f});
    return street(column, 6);
  };
  CHECK(to_last_over_sensor(1.62f) == 1);
  CHECK(to_last_over_sensor(1.5f) == 0);
  // Column 1460: rings 5 and 6 under the sensor, ring 7 over it, the column's last.
  const auto on_to_over_sensor = [&](float top_z) {
    std::vector<Return> column;
    wall(column, 3.94f, 4, top_z);
    column.push_back({5, 16.56f, 1.13f});
    column.push_back({6, 28.28f, 1.64f});
    column.push_back({7, 96.74f, 4.6f});
    return street(column, 5);
  };
  CHECK(on_to_over_sensor(1.5f) == 1);
  CHECK(on_to_over_sensor(1.1f) == 0);
}

TEST_CASE("column profiles: a valley's far side rising on behind a convex shoulder is ground",
          "[detector][profiles]") {
  // Sim hills_s702 (frame 4, column 800): the vehicle low in a valley, the column climbing
  // its side at 0.23 to 11 m; ring 8 passes over a convex shoulder and meets the side rising
  // on gently (0.08) 24 m out, half a metre under the climb extrapolated (a lower surface);
  // ring 9 meets it rising at 0.24 again 29 m out. Level 2 follows the side everywhere.
  const float r[] = {5.15f, 5.56f, 6.53f, 7.14f, 7.78f, 8.61f, 9.62f, 11.17f, 23.67f, 29.08f};
  const float z[] = {0.59f, 0.68f, 0.93f, 1.09f, 1.28f, 1.51f, 1.79f, 2.15f, 3.19f, 4.50f};
  Scan s;
  for (int ring = 0; ring < 10; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
  const auto on_side = [&](float keep_gradient_rise) {
    std::vector<std::uint8_t> steep;
    mark_steep(s.cloud, steep);
    ProfileParams p;
    p.sensor_z = 1.8f;
    p.keep_gradient_rise = keep_gradient_rise;
    std::vector<float> height(s.cloud.size(), 0.f);
    const std::vector<float> plane(s.cloud.size(), std::nanf(""));
    std::vector<std::int32_t> point_bin(s.cloud.size(), 0);
    const std::int32_t cell_of_bin[] = {0};
    const CellState cell_state[] = {CellState::refined};
    std::vector<std::uint8_t> ground;
    ColumnProfiles().label(s.cloud, steep.data(), {point_bin.data(), cell_of_bin, cell_state},
                           plane, p, ground, height);
    return ground;
  };
  const ProfileParams defaults;
  const auto ground = on_side(defaults.keep_gradient_rise);
  for (int ring = 0; ring < 10; ++ring) CHECK(ground[static_cast<std::size_t>(ring)] == 1);
  // Ring 8's rise taken as level (the shoulder gradient's threshold): ring 9 stands 1.3 m
  // over it, more than a rise allows.
  CHECK(on_side(defaults.shoulder_gradient)[9] == 0);

  // Sim fences_s3 (tilted, frame 1, column 1532): the road to 8 m, a low wall there, fence
  // tops the walk takes at 12.6-20.7 m, the last rising only 0.02 from the one before (under
  // the climb extrapolated), then a wall's foot 35 m out. Kept, that gentle rise would carry
  // the profile onto the wall's foot (steep_band_m); taken as level it stays 0.3 m under it.
  Scan f;
  const float fr[] = {5.98f, 6.82f, 7.88f, 8.26f, 8.28f, 12.56f, 14.61f, 20.74f, 35.08f, 35.10f};
  const float fz[] = {0.01f, 0.f, 0.f, 0.2f, 0.5f, 0.21f, 0.45f, 0.57f, 0.86f, 2.09f};
  const int ftruth[] = {1, 1, 1, 2, 2, 2, 2, 2, 2, 2};
  for (int ring = 0; ring < 10; ++ring) add(f, ring, 0, fr[ring], fz[ring], ftruth[ring]);
  const std::vector<float> level2 = {0.05f, 0.05f, -0.01f, 0.2f, 0.49f,
                                     0.23f, 0.48f, 0.69f, 1.06f, 2.28f};
  CHECK(label(f, level2, {}, true).ground[8] == 0);
}

TEST_CASE("column profiles: a hillside rising from beside the vehicle is ground",
          "[detector][profiles]") {
  // Sim hills_s4103 at Hi-Res (frame 1, column 1100): the lowest ring (-10 degrees) meets a
  // hillside 5.6 m out and 0.98 m up, just over the start's allowance (0.25 m + 0.12 per m),
  // and each higher ring meets it farther and higher, climbing at 0.4-0.5; level 2, fitted
  // to ground of its own there, lies through every return.
  const std::vector<ColumnReturn> hillside = {
      {0, 5.62f, 0.982f, 0.f}, {1, 5.84f, 1.082f, 0.f}, {2, 6.09f, 1.187f, 0.f},
      {3, 6.39f, 1.297f, 0.f}, {4, 6.64f, 1.425f, 0.f}, {5, 6.93f, 1.563f, 0.f},
      {6, 7.26f, 1.711f, 0.f}, {7, 7.61f, 1.874f, 0.f}};
  for (const int g : label_column(hillside)) CHECK(g == 1);
  // With only one return going on from it (ring 2; ring 1 lies within 0.3 m of ring 0, and
  // the column ends there), the first return is no climb the column shows.
  const std::vector<ColumnReturn> short_column(hillside.begin(), hillside.begin() + 3);
  for (const int g : label_column(short_column)) CHECK(g == 0);
}

TEST_CASE("column profiles: a valley's far side rising back under the vehicle's ground is ground",
          "[detector][profiles]") {
  // Sim hills_s1903 (frame 1, column 20): the column falls into a valley 2.3 m under the
  // vehicle's ground (ring 3, 25.9 m out) and rises back up its far side (rings 4-6, 29.9 to
  // 38.5 m). Ring 4 stands 0.76 m over the descent extrapolated, more than the walk allows
  // over 4 m; level 2, fitted to ground of its own there, lies through every return.
  const std::vector<ColumnReturn> valley = {{0, 8.2f, -0.434f, 0.f},  {1, 10.6f, -0.669f, 0.f},
                                            {2, 17.6f, -1.651f, 0.f}, {3, 25.9f, -2.340f, 0.f},
                                            {4, 29.9f, -1.909f, 0.f}, {5, 33.6f, -1.174f, 0.f},
                                            {6, 38.5f, -0.253f, 0.f}};
  for (const int g : label_column(valley)) CHECK(g == 1);
  // Sim fences_s2603 (frame 4, column 930): level road to 19 m, then a face 0.7 and 1.4 m
  // up at 21.1 and 23.3 m that level 2 was fitted to. Over the vehicle's ground and under
  // the sensor, it is no terrain climbing on.
  const std::vector<ColumnReturn> face = {{0, 6.8f, 0.017f, -0.026f},  {1, 7.8f, 0.022f, -0.03f},
                                          {2, 9.2f, 0.032f, -0.033f},  {3, 11.2f, 0.051f, -0.029f},
                                          {4, 14.2f, 0.082f, -0.024f}, {5, 19.1f, 0.15f, 0.002f},
                                          {6, 21.1f, 0.709f, -0.005f}, {7, 23.3f, 1.408f, -0.058f}};
  const auto labels = label_column(face);
  CHECK(labels[6] == 0);
  CHECK(labels[7] == 0);
}

TEST_CASE("column profiles: a valley's far side past a floor between two rings is ground",
          "[detector][profiles]") {
  // Sim hills_s605 frame 2, column 941: the column falls at 0.105-0.126 to ring 3 (24 m out,
  // 1.9 m down); ring 4, 3.2 m farther, stands 0.46 m over ring 3 but 0.86 m over the descent
  // extrapolated, more than the walk allows (0.64 m); ring 5 rises on at 0.18. Level 2 has
  // no ground of its own here. Returns ring 4's label.
  const auto ring4 = [](float ring4_z, float ring5_z, const ProfileParams& p) {
    Scan s;
    const float r[] = {6.83f, 8.1f, 11.38f, 24.02f, 27.25f, 30.8f};
    const float z[] = {0.1f, 0.06f, -0.29f, -1.88f, ring4_z, ring5_z};
    for (int ring = 0; ring < 6; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
    return label_by_cell(s, {}, {}, std::vector<bool>(s.cloud.size(), false), nullptr, false, p)
        .ground[4];
  };
  const ProfileParams defaults;
  CHECK(ring4(-1.42f, -0.77f, defaults) == 1);
  ProfileParams off;
  off.valley_far_side = false;
  CHECK(ring4(-1.42f, -0.77f, off) == 0);  // the rule off
  // Ring 5 rising on less steeply than the chord to ring 4 (0.08 against 0.14): a low top,
  // the ground going on beyond it.
  CHECK(ring4(-1.42f, -1.14f, defaults) == 0);
  // Ring 4 0.7 m over ring 3, more than the allowance from ring 3's own level too, ring 5
  // rising on at 0.25.
  CHECK(ring4(-1.18f, -0.29f, defaults) == 0);
}

TEST_CASE("column profiles: past a hidden top, a return on a measured level-2 surface is ground",
          "[detector][profiles]") {
  // Sim hills_s702 (frame 4, column 600): the column climbs a valley's side to 2.7 m (over
  // the sensor) 14.5 m out; ring 10, the column's last return, meets the side 36 m out, 2.5
  // times as far: past_hidden_top's shed on a bank's top, but level 2, fitted to ground of
  // its own there, lies through it.
  const auto last_return = [](float level2_h, bool measured) {
    Scan s;
    const float r[] = {5.56f, 6.05f, 6.56f, 7.2f, 7.85f, 8.61f, 9.55f, 10.66f, 12.1f, 14.49f, 36.23f};
    const float z[] = {0.48f, 0.57f, 0.69f, 0.82f, 1.f, 1.21f, 1.46f, 1.77f, 2.17f, 2.71f, 5.12f};
    for (int ring = 0; ring < 11; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
    std::vector<float> level2(s.cloud.size(), 0.f);
    level2.back() = level2_h;
    std::vector<bool> measured_at(s.cloud.size(), true);
    measured_at.back() = measured;
    return label_by_cell(s, level2, {}, measured_at).ground.back();
  };
  CHECK(last_return(0.f, true) == 1);
  CHECK(last_return(0.f, false) == 0);   // level 2 only extrapolated there
  CHECK(last_return(0.15f, true) == 0);  // off the level-2 surface (a shed's roof)
}

TEST_CASE("column profiles: terrain climbing on over the sensor on a measured level 2 is ground",
          "[detector][profiles]") {
  // Sim hills_s702 (frame 1, column 950): the column climbs a valley's side to 11 m, ring 7
  // lands on a gentle stretch 22 m out (taken as level), ring 8 meets the side rising at
  // 0.2 again 26 m out, 0.8 m over the level profile (more than a rise allows over 4 m),
  // over the sensor (1.8 m); ring 9 goes on rising at 0.24. Level 2 follows the side.
  const float r[] = {5.47f, 5.95f, 6.55f, 7.26f, 8.14f, 9.34f, 11.37f, 21.66f, 25.81f, 30.6f};
  const float z[] = {0.5f, 0.59f, 0.69f, 0.81f, 0.96f, 1.14f, 1.36f, 1.58f, 2.41f, 3.56f};
  struct Case {
    float z_offset_far = 0.f;   // added to rings 7-9
    float ring9_z = 3.56f;      // ring 9's height
    float ring9_level2 = 0.f;   // ring 9's height over level 2
    bool ring8_measured = true;  // level 2 has ground of its own under ring 8
  };
  const auto ring8 = [&](const Case& c) {
    Scan s;
    for (int ring = 0; ring < 10; ++ring) {
      const float zr = ring == 9 ? c.ring9_z : z[ring];
      add(s, ring, 0, r[ring], zr + (ring >= 7 ? c.z_offset_far : 0.f), 1);
    }
    std::vector<float> level2(s.cloud.size(), 0.f);
    level2[9] = c.ring9_level2;
    std::vector<bool> measured(s.cloud.size(), true);
    measured[8] = c.ring8_measured;
    return label_by_cell(s, level2, {}, measured).ground[8];
  };
  CHECK(ring8({}) == 1);
  CHECK(ring8({.ring8_measured = false}) == 0);  // level 2 only extrapolated there
  CHECK(ring8({.ring9_level2 = 0.2f}) == 0);     // the next return off the level-2 surface
  CHECK(ring8({.ring9_z = 1.6f}) == 0);  // the next ring falls past it: a fence line's top
  CHECK(ring8({.z_offset_far = -1.f}) == 0);  // under the sensor, where level 2 may lie on a
                                              // fence line's tops
}

TEST_CASE("column profiles: terrain steepening over the sensor, each ring farther and higher",
          "[detector][profiles]") {
  // Sim hills_s2301 (frame 2, column 1355): the column climbs a hillside at 0.11 to ring 9,
  // 26.9 m out and 1.5 m over the sensor (1.8 m); there the side steepens to 0.36, and
  // rings 10-12 meet it 30, 37 and 47 m out, each rising from the one before more steeply
  // than its ray. Ring 10 lies 0.85 m over the climb extrapolated (a rise over 3.4 m allows
  // 0.66 m), and level 2 lags the steepening (0.85-3.8 m under rings 10-12).
  struct Case {
    float z10 = 4.51f, z11 = 6.36f, z12 = 9.36f;
    bool ring12 = true;
    float h11 = 2.f;         // ring 11's height over level 2
    bool near_rings = true;  // rings 0-8 in this column (else only in the next: dropped out)
  };
  const auto ring10 = [](const Case& c) {
    const float r[] = {6.1f, 6.7f, 7.3f, 8.f, 8.8f, 9.9f, 11.f, 12.7f, 17.1f, 26.9f};
    const float z[] = {0.25f, 0.34f, 0.46f, 0.6f, 0.79f, 1.01f, 1.29f, 1.65f, 2.17f, 3.28f};
    Scan s;
    std::vector<float> level2;
    for (int ring = 0; ring < 10; ++ring) {
      add(s, ring, c.near_rings || ring == 9 ? 0 : 1, r[ring], z[ring], 1);
      level2.push_back(0.f);
    }
    const std::size_t k = s.cloud.size();
    add(s, 10, 0, 30.3f, c.z10, 1);
    add(s, 11, 0, 36.6f, c.z11, 1);
    if (c.ring12) add(s, 12, 0, 47.4f, c.z12, 1);
    for (const float h : {0.85f, c.h11, 3.8f}) level2.push_back(h);
    level2.resize(s.cloud.size());
    return label(s, level2, {}, true).ground[k];
  };
  CHECK(ring10({}) == 1);
  CHECK(ring10({.ring12 = false}) == 0);  // one rising return, then the sky: a crown's top
  // Ring 9 the column's first return: no climb walked, the gradient only a chord from
  // the start.
  CHECK(ring10({.near_rings = false}) == 0);
  // Lying 0.42 m over the chord from ring 9 to ring 11 (on level 2, so the kink is not
  // taken back from there): a bush on the rise, not the rise.
  CHECK(ring10({.z11 = 5.6f, .h11 = 0.2f}) == 0);
  // Bending the gradient up by 0.4 (more than 0.3), though on the chord to ring 11.
  CHECK(ring10({.z10 = 5.01f, .z11 = 7.5f, .z12 = 10.5f}) == 0);
}

TEST_CASE("column profiles: far past a climb, a return past a face rises from the face's foot",
          "[detector][profiles]") {
  // Sim bank_s1001 (frame 3, column 219): rings 0-9 climb the bank to 18.7 m (2.75 m up),
  // rings 10-12 meet a building's face 27.7 m out, ring 13 a tree crown 38.7 m out, 9.28 m
  // up. The bank's slope extrapolated 20 m passes 0.75 m under the crown (within the
  // allowance past an obstacle); the ground at the face lies at or under its lowest return
  // (4.19 m), and from there the crown is 1.9 m over the slope. The level-2 surface lies at
  // each return (h 0: only the walk decides).
  const std::vector<ColumnReturn> bank = {
      {0, 7.9f, -0.337f, 0.f},   {1, 8.51f, -0.186f, 0.f},  {2, 9.14f, 0.f, 0.f},
      {3, 9.87f, 0.213f, 0.f},   {4, 10.74f, 0.456f, 0.f},  {5, 11.73f, 0.747f, 0.f},
      {6, 12.94f, 1.094f, 0.f},  {7, 14.42f, 1.519f, 0.f},  {8, 16.3f, 2.053f, 0.f},
      {9, 18.72f, 2.748f, 0.f},  {10, 27.65f, 4.185f, 0.f}, {11, 27.69f, 5.164f, 0.f},
      {12, 27.68f, 6.148f, 0.f}, {13, 38.67f, 9.278f, 0.f}};
  CHECK(label_column(bank) == std::vector<int>{1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0});
  // Ground going on from the face's foot at the profile's gradient (within 0.06) is the
  // climb resuming, as past any obstacle: the face 0.91 m higher, ring 13 0.4 m lower
  // (0.62 m over the slope drawn from the face's foot, 11 m on).
  std::vector<ColumnReturn> climbing = bank;
  for (std::size_t k = 10; k <= 12; ++k) climbing[k].z += 0.91f;
  climbing.back().z -= 0.4f;
  CHECK(label_column(climbing).back() == 1);
  // Without a long climb extrapolated the profile is no guess: a level road to 10 m, a car
  // in a dip 12 m out (its side's lowest return 0.35 m under the road), the road rising out
  // of the dip 20 m out, 0.2 m up.
  CHECK(label_column({{0, 6.f, 0.f, 0.f},
                      {1, 8.f, 0.f, 0.f},
                      {2, 10.f, 0.f, 0.f},
                      {3, 12.f, -0.35f, -0.35f},
                      {4, 12.f, 0.05f, 0.05f},
                      {5, 12.f, 0.45f, 0.45f},
                      {6, 20.f, 0.2f, 0.2f}}) == std::vector<int>{1, 1, 1, 0, 0, 0, 1});
}
