// Column profiles, rule 4 (docs/detector.md, "Column profiles"): ground returns raised over
// the level-2 surface need a raised neighbour; raised groups, objects' tops, refuted rises.
#include <catch2/catch.hpp>
#include <cmath>
#include <utility>
#include <vector>

#include "column_scan.hpp"

using namespace vlpground::detail;
using namespace column_scan;

TEST_CASE("column profiles: a single ring raised over the level-2 surface is dropped",
          "[detector][profiles]") {
  Scan s;
  // One column: ground at 6, 7.5, 9 m; ring 3 a low fence line at 10.5 m, 0.38 m up (the
  // walk alone would take it); ground at 12 m. The level-2 surface is the level road.
  for (int ring = 0; ring < 5; ++ring) {
    const bool fence = ring == 3;
    add(s, ring, 0, ring_range(ring), fence ? 0.38f : 0.f, fence ? 2 : 1);
  }
  CHECK(label(s, s.cloud.z).ground == std::vector<std::uint8_t>{1, 1, 1, 0, 1});
}

TEST_CASE("column profiles: a low line that kinks the profile up is a single rise",
          "[detector][profiles]") {
  // Sim fences (seed 103, where rings 4-6 each meet a low fence): ground to 12 m, then a
  // fence line 1.1 m farther and 0.26 m up, under single_rise_m over the level-2 surface;
  // ground again at 20 m. Reached by a kink (the gradient bends up by 0.24), it is dropped.
  Scan fence;
  const float fr[] = {6.f, 8.f, 10.f, 12.f, 13.1f, 20.f}, fz[] = {0, 0, 0, 0, 0.26f, 0};
  for (int ring = 0; ring < 6; ++ring) add(fence, ring, 0, fr[ring], fz[ring], ring == 4 ? 2 : 1);
  CHECK(label(fence, fence.cloud.z).ground == std::vector<std::uint8_t>{1, 1, 1, 1, 0, 1});
  // The same height over a level-2 surface that misses a gentle rise (bending a few
  // hundredths at each ring) stays ground.
  Scan hill;
  const float hr[] = {6.f, 8.f, 10.f, 12.f}, hz[] = {0, 0.06f, 0.2f, 0.4f};
  for (int ring = 0; ring < 4; ++ring) add(hill, ring, 0, hr[ring], hz[ring], 1);
  CHECK(label(hill, {0, 0, 0, 0.26f}).ground == std::vector<std::uint8_t>(4, 1));
}

TEST_CASE("column profiles: a kinked rise is vouched for only by a raised return close beyond",
          "[detector][profiles]") {
  // Sim fences (seed 3): ring 4 meets a fence 3.1 m past ground, 0.55 m up (the walk takes
  // it, kinking the profile up); the next ground return is 38 m farther, over a level-2
  // surface extrapolated beyond the grid that lies 0.5 m under it. That far return does not
  // vouch for the fence line.
  Scan fence;
  const float fr[] = {6.f, 10.f, 15.f, 20.5f, 23.6f, 62.f};
  const float fz[] = {0, 0.03f, 0.07f, 0.12f, 0.67f, 0.82f};
  for (int ring = 0; ring < 6; ++ring) add(fence, ring, 0, fr[ring], fz[ring], ring == 4 ? 2 : 1);
  CHECK(label(fence, {0, 0, 0, 0, 0.55f, 0.5f}).ground ==
        std::vector<std::uint8_t>{1, 1, 1, 1, 0, 1});
  // A bank's top edge reached by a kink: the top 1 m beyond, raised too, vouches for it.
  Scan bank;
  const float br[] = {6.f, 8.f, 10.f, 11.f, 12.f}, bz[] = {0, 0, 0, 0.35f, 0.37f};
  for (int ring = 0; ring < 5; ++ring) add(bank, ring, 0, br[ring], bz[ring], 1);
  CHECK(label(bank, {0, 0, 0, 0.35f, 0.37f}).ground == std::vector<std::uint8_t>(5, 1));
}

TEST_CASE("column profiles: an object standing out does not vouch for a single rise",
          "[detector][profiles]") {
  // Sim fences (seed 3): a long low fence line 24.6 m out (ring 4 over 41 columns, 0.56 m
  // over level 2) and, in five of its columns, a facade's ring line standing out against the
  // sky (ring 5). The walk takes the facade line as ground rising on from the fence; it is
  // a silhouette (rule 5), so it does not vouch for the fence line under it (rule 4).
  Scan s;
  const float gr[] = {6.f, 10.f, 15.f, 20.5f}, gz[] = {0, 0.03f, 0.07f, 0.12f};
  std::vector<float> level2;
  auto put = [&](int ring, int col, float r, float z, int truth, float h) {
    add(s, ring, col, r, z, truth);
    level2.push_back(h);
  };
  for (int ring = 0; ring < 4; ++ring) {
    for (int col = 0; col <= 40; ++col) put(ring, col, gr[ring], gz[ring], 1, 0.f);
  }
  for (int col = 0; col <= 40; ++col) put(4, col, 24.6f, 0.62f, 2, 0.56f);
  for (int col = 18; col <= 22; ++col) put(5, col, 29.5f, 1.39f, 2, 1.3f);
  const auto ground = label(s, level2).ground;
  for (std::size_t i = 0; i < ground.size(); ++i) {
    INFO("ring " << s.cloud.ring[i] << " column " << s.cloud.column[i]);
    CHECK(ground[i] == (s.truth[i] == 1 ? 1 : 0));
  }
}

TEST_CASE("column profiles: a return level with the ground before it is not a single rise",
          "[detector][profiles]") {
  // A levee: the road at 7 m, its shoulder at 8.4 m, the fields 1.9 m lower at 19.6 m. The
  // level-2 cell under the shoulder was fitted to the fields: the shoulder is 1.86 m over
  // it, with neither column neighbour raised, but level with the road before it.
  Scan s;
  add(s, 0, 0, 7.f, 0.f, 1);
  add(s, 1, 0, 8.4f, -0.04f, 1);
  add(s, 2, 0, 19.6f, -1.9f, 1);
  CHECK(label(s, {0.f, 1.86f, 0.f}).ground == std::vector<std::uint8_t>{1, 1, 1});
}

TEST_CASE("column profiles: a single rise over the sensor on a long ring run is the terrain",
          "[detector][profiles]") {
  // Sim hills_s603_20hz (frame 1, column 392): rings 0-7 on a hill rising ahead of the
  // vehicle, ring 8 (the column's last return) 27.4 m out, 2.24 m up, over the sensor and
  // 0.49 m over the level-2 surface, which has no ground of its own there (`measured`
  // false: the cells only extrapolate). The same column repeats over `columns` degrees, so
  // that ring 8's run along its ring is 0.48 m a column long. Returns whether ring 8 is
  // ground in the middle column.
  const auto ring8_ground = [](int columns, float z8, bool measured) {
    const std::vector<ColumnReturn> hill = {
        {0, 6.74f, -0.036f, 0.f},    {1, 7.79f, -0.03f, -0.01f}, {2, 9.13f, -0.007f, 0.02f},
        {3, 10.84f, 0.048f, -0.01f}, {4, 13.03f, 0.164f, 0.f},   {5, 15.65f, 0.392f, 0.f},
        {6, 18.74f, 0.778f, 0.02f},  {7, 22.43f, 1.367f, 0.f},   {8, 27.42f, z8, 0.49f}};
    Scan s;
    std::vector<float> level2;
    std::vector<bool> measured_by_point;
    for (const ColumnReturn& q : hill) {
      for (int col = 0; col < columns; ++col) {
        add(s, q.ring, col, q.r, q.z, 1);
        level2.push_back(q.h);
        measured_by_point.push_back(q.ring != 8 || measured);
      }
    }
    const Labels out = label_by_cell(s, level2, {}, measured_by_point);
    return out.ground[static_cast<std::size_t>(8 * columns + columns / 2)] == 1;
  };
  CHECK(ring8_ground(60, 2.236f, false));   // a run of 28 m
  CHECK(!ring8_ground(18, 2.236f, false));  // 8 m: an object's top, as before
  CHECK(!ring8_ground(60, 2.236f, true));   // the level-2 surface has ground there
  CHECK(!ring8_ground(60, 1.7f, false));    // under the sensor (1.8 m)
}

TEST_CASE("column profiles: a column's first return on a long ring run is the terrain",
          "[detector][profiles]") {
  // Sim garage_s1505 Hi-Res (frame 3, column 780): the vehicle pitched on a ramp's upper
  // bend; its lowest ring passes over the parapet behind it to the street 26.9 m out, 2.87 m
  // under the ramp's plane and 3.09 m over the level-2 surface, which only extrapolates the
  // bend there (no ground of its own); the next rings meet a facade 37 m out. The same column
  // repeats over `columns` degrees (0.47 m a column at 26.9 m). With a car side next to the
  // sensor, the street's return is not the column's first. Returns whether the street's
  // return is ground in the middle column.
  const auto street_ground = [](int columns, bool measured, bool car_in_front) {
    Scan s;
    std::vector<float> level2;
    std::vector<bool> measured_by_point;
    const int street = car_in_front ? 3 : 0;
    const auto add_all = [&](int ring, float r, float z, int truth, float h) {
      for (int col = 0; col < columns; ++col) {
        add(s, ring, col, r, z, truth);
        level2.push_back(h);
        measured_by_point.push_back(ring != street || measured);
      }
    };
    if (car_in_front) {
      for (int ring = 0; ring < street; ++ring)
        add_all(ring, 4.5f, 0.4f + 0.3f * static_cast<float>(ring), 2, 0.4f);
    }
    add_all(street, 26.94f, -2.87f, 1, 3.09f);
    // The facade, its lowest return here 0.6 m over the street (at -2.86 m in the capture):
    // a face rising from the street would vouch for it alone (floor_under_face).
    for (int ring = street + 1; ring < street + 6; ++ring)
      add_all(ring, 37.f, -2.26f + 0.86f * static_cast<float>(ring - street - 1), 2, 3.f);
    const Labels out = label_by_cell(s, level2, {}, measured_by_point);
    return out.ground[static_cast<std::size_t>(street * columns + columns / 2)] == 1;
  };
  CHECK(street_ground(60, false, false));   // a run of 28 m
  CHECK(!street_ground(18, false, false));  // 8 m: an object's top (a tree top in a valley)
  CHECK(!street_ground(60, true, false));   // the level-2 surface has ground there
  CHECK(!street_ground(60, false, true));   // past a car: not what the lowest ring met first
}

TEST_CASE("column profiles: a return on the chord of its column's ground is no single rise",
          "[detector][profiles]") {
  // A valley's far side (sim hills, seed 4): ring 6 is 0.35 m over a level-2 cell that is
  // off there, its neighbours are not; it lies under the chord joining rings 5 and 7.
  const float r[] = {7.15f, 8.42f, 10.12f, 12.47f, 15.41f, 18.82f, 22.45f, 26.34f, 30.92f};
  const float z[] = {-0.13f, -0.16f, -0.19f, -0.19f, -0.11f, 0.13f, 0.60f, 1.31f, 2.31f};
  Scan s;
  for (int ring = 0; ring < 9; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
  std::vector<float> level2(s.cloud.size(), 0.f);
  level2[6] = 0.35f;
  CHECK(label(s, level2).ground == std::vector<std::uint8_t>(9, 1));
}

TEST_CASE("column profiles: a column's first return level with the vehicle's ground stays ground",
          "[detector][profiles]") {
  // A levee whose road ring 0 meets at 7.3 m; ring 1 passes over the levee's side to the
  // fields 1.9 m lower. The level-2 cell was fitted to the fields: ring 0 is 1.87 m over
  // it with no raised column neighbour and no ground return before it but the start.
  const auto first = [](bool car_in_front, float z0) {
    Scan s;
    if (car_in_front) {  // a car side next to the sensor (steep), its lowest ring 0
      for (int ring = 0; ring <= 2; ++ring) add(s, ring, 0, 4.5f, 0.4f + 0.3f * static_cast<float>(ring), 2);
    }
    const int r0 = car_in_front ? 3 : 0;
    add(s, r0, 0, 7.3f, z0, 1);
    add(s, r0 + 1, 0, 16.5f, -1.9f, 1);
    std::vector<float> level2(s.cloud.size(), 0.f);
    level2[static_cast<std::size_t>(r0)] = z0 + 1.9f;
    return label(s, level2).ground[static_cast<std::size_t>(r0)];
  };
  CHECK(first(false, -0.03f) == 1);  // the road beside the vehicle
  CHECK(first(false, -0.9f) == 0);   // under it: a bush in the fields, as far as rule 4 knows
  CHECK(first(true, 0.1f) == 0);     // past a car: something else at that height (a roof)
}

TEST_CASE(
    "column profiles: a column's only ground under the vehicle that a face stands on is the floor",
    "[detector][profiles]") {
  // Sim garage_s2205 Hi-Res (frame 0, column 190): the vehicle on the street, a ramp falling
  // ahead; ring 0 on the garage's floor 22.6 m out, 2.12 m under the street and 0.5 m over
  // the level-1 plane that level 2 kept there; rings 1-6 on the back wall 28.3 m out (from
  // wall_z up). Returns whether ring 0 is ground.
  const auto floor_ground = [](float floor_z, bool wall, float wall_z) {
    Scan s;
    add(s, 0, 0, 22.6f, floor_z, 1);
    if (wall) {
      for (int ring = 1; ring <= 6; ++ring)
        add(s, ring, 0, 28.3f, wall_z + 0.66f * static_cast<float>(ring - 1), 2);
    }
    std::vector<float> level2(s.cloud.size(), 3.f);
    level2[0] = 0.5f;
    return label(s, level2).ground[0] == 1;
  };
  CHECK(floor_ground(-2.12f, true, -2.46f));  // the wall rises from the floor
  CHECK(floor_ground(-2.12f, true, -1.7f));   // its lowest return 0.42 m up the wall
  CHECK(!floor_ground(-2.12f, true, -1.5f));  // a face starting 0.62 m over it: a top
  CHECK(!floor_ground(-2.12f, false, 0.f));   // no face: a top in a hollow, as before
  CHECK(!floor_ground(0.4f, true, 0.06f));    // over the vehicle's ground: a top
}

TEST_CASE("column profiles: the vehicle's ground past a bush taken, then dropped, stays ground",
          "[detector][profiles]") {
  // Sim embankment (seed 3, 5 Hz): ring 0 meets a bush on the levee's road 0.35 m high at
  // 5.8 m, which the walk takes (a gentle rise from the start) and which then stands out as
  // a silhouette; ring 1 sees the road past it at 8.4 m, level with the start, 1.9 m over
  // the level-2 cell fitted to the fields; ring 2 is on the fields. No ground is left before
  // ring 1's return and no obstacle was refused before it: the vehicle's ground going on.
  // Beside the bush (columns 0-1 and 5-6) ring 0 meets the road at 7.3 m.
  Scan s;
  std::vector<float> level2;
  const auto bush = [](int col) { return col >= 2 && col <= 4; };
  for (int col = 0; col <= 6; ++col) {
    add(s, 0, col, bush(col) ? 5.8f : 7.3f, bush(col) ? 0.35f : -0.03f, bush(col) ? 2 : 1);
    level2.push_back(bush(col) ? 2.25f : 0.f);
  }
  for (int col = 0; col <= 6; ++col) {
    add(s, 1, col, 8.4f, -0.04f, 1);
    level2.push_back(bush(col) ? 1.86f : 0.f);
  }
  for (int col = 0; col <= 6; ++col) {
    add(s, 2, col, 19.7f, -1.9f, 1);
    level2.push_back(0.f);
  }
  const auto ground = label(s, level2).ground;
  for (std::size_t i = 0; i < ground.size(); ++i) {
    INFO("ring " << s.cloud.ring[i] << " column " << s.cloud.column[i]);
    CHECK(ground[i] == (s.truth[i] == 1 ? 1 : 0));
  }
}

TEST_CASE("column profiles: raised neighbours do not vouch for a bump standing out of both",
          "[detector][profiles]") {
  // Fields 2 m under the road, seen at 10, 20 and 40 m; ring 2 at 25 m meets a bush
  // `bush_m` over them (a gentle rise from ring 1, within the allowance). The level-2 cells
  // lie 0.62 m under the fields: every return is raised, the bush by its height more.
  const auto bush = [](float bush_m, float level2_rise = 0.f) {
    Scan s;
    const float r[] = {10.f, 20.f, 25.f, 40.f};
    for (int ring = 0; ring < 4; ++ring) {
      add(s, ring, 0, r[ring], ring == 2 ? -2.f + bush_m : -2.f, ring == 2 ? 2 : 1);
    }
    std::vector<float> level2 = {0.62f, 0.62f, 0.62f + bush_m - level2_rise, 0.62f};
    return label(s, level2).ground;
  };
  CHECK(bush(0.65f) == std::vector<std::uint8_t>{1, 1, 0, 1});
  // 0.4 m over the chord: a hump the fields may have, raised with its neighbours.
  CHECK(bush(0.4f) == std::vector<std::uint8_t>{1, 1, 1, 1});
  // Where the level-2 surface rises 0.4 m there too, it is no bump over that surface.
  CHECK(bush(0.65f, 0.4f) == std::vector<std::uint8_t>{1, 1, 1, 1});
}

TEST_CASE("column profiles: a group of raised returns standing out of the ground on both sides "
          "is an object", "[detector][profiles]") {
  // Fields 2 m under the road, seen at 10, 20 and 40 m; rings 2 and 3 meet a car roof
  // `roof_m` over them, `roof_length_m` long (a gentle rise from ring 1, within the
  // allowance). The level-2 cells lie 0.1 m under the fields; the roof's two returns are
  // raised by its height more and vouch for each other (rule 4).
  const auto roof = [](float roof_m, float roof_length_m = 1.5f) {
    Scan s;
    const float r[] = {10.f, 20.f, 25.f, 25.f + roof_length_m, 40.f};
    for (int ring = 0; ring < 5; ++ring) {
      const bool on_roof = ring == 2 || ring == 3;
      add(s, ring, 0, r[ring], on_roof ? -2.f + roof_m : -2.f, on_roof ? 2 : 1);
    }
    std::vector<float> level2 = {0.1f, 0.1f, 0.1f + roof_m, 0.1f + roof_m, 0.1f};
    return label(s, level2).ground;
  };
  CHECK(roof(0.65f) == std::vector<std::uint8_t>{1, 1, 0, 0, 1});
  // 0.4 m over the fields on both sides: a hump the fields may have.
  CHECK(roof(0.4f) == std::vector<std::uint8_t>{1, 1, 1, 1, 1});
  // Longer than bump_group_max_m: a rise of the terrain, left to rule 4.
  CHECK(roof(0.65f, 6.f) == std::vector<std::uint8_t>{1, 1, 1, 1, 1});
}

TEST_CASE("column profiles: a raised group that goes on rising as the chord to it is a crest",
          "[detector][profiles]") {
  // Sim hills_s2304 (Puck Hi-Res, frame 2): the vehicle just below a crest; rings 0-3 meet
  // it 7.1-9.8 m out, 0.6-0.82 m over the ground under the vehicle (level 2 lies there),
  // rising on from it at 0.08 as the chord from under the vehicle to ring 0 does; ring 4
  // meets the far side 56 m out, 2.7 m lower. Each stands more than drop_m over the ground
  // before and after it, as a car roof's returns do, but a roof or a box's top is level:
  // it does not go on rising as the chord from the ground before it.
  const auto crest = [](const std::vector<float>& z,
                        const std::vector<float>& r = {7.07f, 7.69f, 8.53f, 9.77f, 55.76f}) {
    return label(ground_column(r, z), z).ground;  // level 2 at the vehicle's ground
  };
  using Labels = std::vector<std::uint8_t>;
  CHECK(crest({0.6f, 0.68f, 0.75f, 0.82f, -2.71f}) == Labels{1, 1, 1, 1, 1});
  // A level top 0.6 m up, 2.7 m deep: an object's.
  CHECK(crest({0.6f, 0.6f, 0.6f, 0.6f, -2.71f}) == Labels{0, 0, 0, 0, 1});
  // The ground behind it level with the vehicle's: an object on that ground.
  CHECK(crest({0.6f, 0.68f, 0.75f, 0.82f, 0.f}) == Labels{0, 0, 0, 0, 1});
  // Two returns 0.6 m apart: too short to show that it rises on (a fence's top).
  CHECK(crest({0.6f, 0.68f, -2.71f}, {7.07f, 7.69f, 55.76f}) == Labels{0, 0, 1});
}

TEST_CASE("column profiles: a first raised group over cells fallen under the vehicle is a crest",
          "[detector][profiles]") {
  // Sim hills_s2305 (Puck Hi-Res, frame 1, column 850): the vehicle in a hollow; rings 0-4
  // climb a hill's flank 6.8-10.3 m out, 0.65-1.0 m up, rising on at 0.1 as the chord from
  // under the vehicle does; ring 5 meets the far side 29.8 m out, 0.12 m up, level with the
  // vehicle's ground. The cells carried the vehicle's surface down behind it: level 2 lies
  // 1.7-2.6 m under the flank (1.07 m under the vehicle's ground at ring 0).
  const std::vector<float> r = {6.8f, 7.4f, 8.1f, 9.0f, 10.3f, 29.8f};
  const std::vector<float> flank = {0.65f, 0.72f, 0.81f, 0.90f, 1.0f, 0.12f};
  const std::vector<float> fallen = {1.72f, 1.87f, 2.05f, 2.27f, 2.56f, 0.f};
  const auto column = [&](const std::vector<float>& z, const std::vector<float>& level2) {
    return label(ground_column(r, z), level2).ground;
  };
  using Labels = std::vector<std::uint8_t>;
  CHECK(column(flank, fallen) == Labels{1, 1, 1, 1, 1, 1});
  // Level 2 only 0.4 m under the vehicle's ground at ring 0 (within drop_m): it may show
  // the ground an object stands on, so the group is dropped as a car roof would be.
  const std::vector<float> shallow = {1.05f, 1.2f, 1.38f, 1.6f, 1.89f, 0.f};
  CHECK(column(flank, shallow) == Labels{0, 0, 0, 0, 0, 1});
  // A level top over the fallen cells: an object's, not terrain rising on.
  CHECK(column({0.65f, 0.65f, 0.65f, 0.65f, 0.65f, 0.12f}, fallen) == Labels{0, 0, 0, 0, 0, 1});
}

TEST_CASE("column profiles: a column's first return climbing on over fallen cells stays ground",
          "[detector][profiles]") {
  // Sim hills_s101 (Puck Hi-Res, frame 1, column 1296): a gentle climb from the vehicle;
  // ring 0 meets it 10.1 m out, 0.2 m up, ring 1 11.3 m out, 0.25 m up, and so on. The cell
  // under ring 0 took a neighbour's surface falling away, 0.68 m under the vehicle's ground
  // there (level 2 0.88 m under ring 0); the rings over it lie on their cells.
  const std::vector<float> r = {10.1f, 11.3f, 12.8f, 14.6f};
  const auto ring0 = [&](float z1, float level2_under_ring0) {
    const std::vector<float> z = {0.2f, z1, 0.32f, 0.43f};
    return label(ground_column(r, z), {level2_under_ring0, 0.f, 0.f, 0.f}).ground[0];
  };
  CHECK(ring0(0.25f, 0.88f) == 1);
  CHECK(ring0(0.15f, 0.88f) == 0);  // the next ground return lower: no climb going on
  CHECK(ring0(0.25f, 0.6f) == 0);   // level 2 only 0.4 m under the vehicle's ground there
}

TEST_CASE("column profiles: a raised group past the column's own ground needs the far side to fall",
          "[detector][profiles]") {
  // Ring 0 on the ground 5 m out, level with the vehicle's and on level 2; rings 1-4 on a
  // top 10-13 m out, 0.65-1.01 m up, rising on as the chord from ring 0 does; ring 5 on the
  // ground 30 m out, 0.1 m up. Level 2 lies 1.2 m under the vehicle's ground beneath the
  // top, but the column has ground of its own before it, level with what lies after it: an
  // object's top on that ground.
  const std::vector<float> r = {5.f, 10.f, 11.f, 12.f, 13.f, 30.f};
  const std::vector<float> z = {0.f, 0.65f, 0.77f, 0.89f, 1.01f, 0.1f};
  CHECK(label(ground_column(r, z), {0.f, 1.85f, 1.97f, 2.09f, 2.21f, 0.f}).ground ==
        std::vector<std::uint8_t>{1, 0, 0, 0, 0, 1});
}

TEST_CASE("column profiles: raised returns ending a column past an obstacle are an object's top",
          "[detector][profiles]") {
  // Sim fences_s101: ring 0 on the road 7.4 m out, rings 1-4 on a 1 m wall 8.1 m out;
  // rings 5 and 6 pass over it to the tops of fences 18 and 25 m out (`z5`, `z6` over the
  // road), taken as a gentle rise past the wall and vouching for each other (rule 4);
  // the higher rings go to the sky. The level-2 surface lies at `level2_z`.
  const auto top_kept = [](float z5, float z6, bool measured, float level2_z = 0.f) {
    const Scan s = wall_then_fence_tops(z5, z6);
    std::vector<float> level2(s.cloud.size());
    for (std::size_t i = 0; i < level2.size(); ++i) level2[i] = s.cloud.z[i] - level2_z;
    const Labels out = label(s, level2, {}, measured);
    REQUIRE(out.ground[0] == 1);
    return std::vector<int>{out.ground[5], out.ground[6]};
  };
  // The level-2 cells there have ground of their own and lie under the tops: dropped.
  CHECK(top_kept(0.41f, 0.66f, true) == std::vector<int>{0, 0});
  // Cells without ground of their own (inherited, or past the fitting area): kept.
  CHECK(top_kept(0.41f, 0.66f, false) == std::vector<int>{1, 1});
  // Ground climbing over the sensor (1.8 m; a bank's face, where the cells lag): kept.
  CHECK(top_kept(0.5f, 1.9f, true) == std::vector<int>{1, 1});
  // Level with the ground under the vehicle where the cells lie 1 m lower (a ramp's
  // street level going on past a car): kept.
  CHECK(top_kept(0.05f, 0.1f, true, -1.f) == std::vector<int>{1, 1});
}

TEST_CASE("column profiles: an object's top needs ground of its own only under its high return",
          "[detector][profiles]") {
  // The fences_s101 column of the test above, with the level-2 surface at z = 0 having
  // ground of its own under ring 5's fence top (`measured5`) or ring 6's (`measured6`),
  // not under the other (past the fitting area, or inherited): fences_s3_hires, a barrier's
  // top met by ring 0 and fence tops farther out in cells without ground of their own.
  const auto top_kept = [](float z5, float z6, bool measured5, bool measured6) {
    const Scan s = wall_then_fence_tops(z5, z6);
    std::vector<bool> measured(s.cloud.size(), true);
    measured[5] = measured5;
    measured[6] = measured6;
    const Labels out = label_by_cell(s, s.cloud.z, {}, measured);
    REQUIRE(out.ground[0] == 1);
    return std::vector<int>{out.ground[5], out.ground[6]};
  };
  // One return more than single_rise_m over ground of the cells' own: the group is dropped.
  CHECK(top_kept(0.41f, 0.66f, true, false) == std::vector<int>{0, 0});
  CHECK(top_kept(0.41f, 0.66f, false, true) == std::vector<int>{0, 0});
  // The only return that high lies over a cell without ground of its own: kept.
  CHECK(top_kept(0.25f, 0.66f, true, false) == std::vector<int>{1, 1});
}

TEST_CASE("column profiles: a column's first two returns on a top, nothing after, are an object",
          "[detector][profiles]") {
  // Sim fences_s3 at Hi-Res: the two lowest rings meet a 0.7 m barrier 7.7 m out (its face
  // just under the top edge, then the top), the rings above pass over it to obstacles or
  // the sky; the level-2 surface lies at z = 0 and has ground of its own.
  const auto kept = [](std::vector<std::pair<float, float>> returns) {
    Scan s;
    for (std::size_t ring = 0; ring < returns.size(); ++ring) {
      add(s, static_cast<int>(ring), 0, returns[ring].first, returns[ring].second, 2);
    }
    const Labels out = label(s, s.cloud.z, {}, true);  // heights over the surface at z = 0
    return std::vector<int>(out.ground.begin(), out.ground.end());
  };
  CHECK(kept({{7.7f, 0.56f}, {7.9f, 0.71f}}) == std::vector<int>{0, 0});
  // Three rings climbing: a bank's face next to the road (the cells lag it): kept.
  CHECK(kept({{6.56f, 0.58f}, {6.81f, 0.7f}, {7.04f, 0.83f}}) == std::vector<int>{1, 1, 1});
  // At most drop_m over the start: a hump the road may have, left to the other rules.
  CHECK(kept({{7.7f, 0.3f}, {7.9f, 0.4f}}) == std::vector<int>{1, 1});
}

TEST_CASE("column profiles: a kinked rise of two rings ending the column is an object's top",
          "[detector][profiles]") {
  // Sim fences_s704 (frame 4, column 700): rings 0-4 on level ground out to 15.4 m, ring 5
  // on a fence 17.1 m out, ring 6 on another 20.7 m out, each taken as a rise from the last
  // (ring 5 kinks the profile up, ring 6 vouches for it close beyond), rings 7-15 on a
  // facade 39.7 m out. The level-2 surface lies at z = 0 and has ground of its own.
  const auto kept = [](std::vector<std::pair<float, float>> rise, bool facade = true) {
    Scan s;
    const float ground[] = {7.04f, 8.17f, 9.68f, 11.88f, 15.35f};
    int ring = 0;
    for (const float r : ground) add(s, ring++, 0, r, 0.f, 1);
    for (const auto& [r, z] : rise) add(s, ring++, 0, r, z, 2);
    for (; facade && ring < 16; ++ring) add(s, ring, 0, 39.65f, 1.19f + 1.39f * static_cast<float>(ring - 7), 2);
    const Labels out = label(s, s.cloud.z, {}, true);  // heights over the surface at z = 0
    for (int g = 0; g < 5; ++g) REQUIRE(out.ground[static_cast<std::size_t>(g)] == 1);
    const auto first = out.ground.begin() + 5;
    return std::vector<int>(first, first + static_cast<std::ptrdiff_t>(rise.size()));
  };
  CHECK(kept({{17.06f, 0.39f}, {20.73f, 0.8f}}) == std::vector<int>{0, 0});
  CHECK(kept({{17.06f, 0.39f}, {20.73f, 0.8f}}, false) == std::vector<int>{0, 0});
  // The kink's first return at most single_rise_m over the level-2 surface: terrain bending
  // up where the cells lag it (bank_s804, the far side of a dip): kept.
  CHECK(kept({{17.06f, 0.25f}, {20.73f, 0.7f}}) == std::vector<int>{1, 1});
  // Three rings climbing on from the kink: a bank's face (the cells lag it): kept.
  CHECK(kept({{17.06f, 0.39f}, {20.73f, 0.8f}, {24.f, 1.2f}}) == std::vector<int>{1, 1, 1});
}

TEST_CASE("column profiles: a kinked rise with a steep step in it is a bank's face",
          "[detector][profiles]") {
  // Sim bank_s4 tilted (frame 2, column 1352): the road, then a bank's face whose rings
  // 3-5 met a steep step (ring 5 a box on it); the level-2 surface lags the face (heights
  // over it `h`) and has ground of its own. The walk takes rings 0-2, 6 and 7.
  Scan s;
  const float r[] = {6.36f, 6.66f, 7.04f, 7.37f, 7.72f, 7.79f, 8.66f, 9.25f};
  const float z[] = {0.2f, 0.36f, 0.54f, 0.74f, 0.96f, 1.23f, 1.47f, 1.77f};
  const float h[] = {0.03f, 0.06f, 0.33f, 0.51f, 0.71f, 0.97f, 1.15f, 1.42f};
  for (int ring = 0; ring < 8; ++ring) add(s, ring, 0, r[ring], z[ring], 1);
  const Labels out = label(s, std::vector<float>(std::begin(h), std::end(h)), {}, true);
  CHECK(std::vector<int>{out.ground[2], out.ground[6], out.ground[7]} ==
        std::vector<int>{1, 1, 1});
}

TEST_CASE("column profiles: a wall's foot on a dropped object's top is no ground",
          "[detector][profiles]") {
  // Sim fences_s1003 (frame 0, column 100): ring 0 on a barrier's top 4.5 m out, taken as a
  // kink and later dropped as a group standing out; rings 1-3 on a face 4.9 m out, ring 1
  // taken as the face's foot on the profile through ring 0; then the road from 15 m.
  const std::vector<ColumnReturn> fence = {{0, 4.54f, 0.716f, 0.79f},   {1, 4.91f, 0.797f, 0.86f},
                                           {2, 4.91f, 0.976f, 1.04f},   {3, 4.91f, 1.15f, 1.22f},
                                           {4, 15.41f, 0.034f, -0.01f}, {5, 21.17f, 0.073f, -0.03f},
                                           {6, 33.05f, 0.192f, -0.04f}};
  CHECK(label_column(fence) == std::vector<int>{0, 0, 0, 0, 1, 1, 1});
  // The same column with a wall 21 m out, whose foot the walk took on the road's profile
  // from 15 m: a ground return kept between, it stays ground.
  std::vector<ColumnReturn> wall = fence;
  wall.back() = {6, 21.2f, 0.95f, 0.85f};
  CHECK(label_column(wall) == std::vector<int>{0, 0, 0, 0, 1, 1, 0});
}

TEST_CASE("column profiles: a rise the neighbouring columns saw the ground under is refuted",
          "[detector][profiles]") {
  // Sim fences_s103: ring 0 on the road 8 m out, ring 1 on a low fence 10 m out (0.2 m up),
  // ring 2 on the top of a second fence 13 m out (0.7 m up); the walk takes both fence lines
  // as a gentle rise and the level-2 cells climbed with them (0.05 m under each). Where the
  // first fence has a gap (`gap_column`), ring 1 passes it and meets the road 12 m out.
  // Columns 1 degree apart: 0.21 m at 12 m, so only the gap's two neighbours lie within
  // refute_lateral_m (0.4 m) of it.
  const auto ring2_ground = [](int gap_column) {
    Scan s;
    std::vector<float> level2;
    constexpr int kWide = 60;  // ring lines longer than silhouette_max_m
    for (int ring = 0; ring < 3; ++ring) {
      for (int col = 0; col < kWide; ++col) {
        if (ring == 0) {
          add(s, 0, col, 8.f, 0.f, 1);
          level2.push_back(0.f);
        } else if (ring == 1 && col == gap_column) {
          add(s, 1, col, 12.f, 0.f, 1);
          level2.push_back(0.f);
        } else {
          add(s, ring, col, ring == 1 ? 10.f : 13.f, ring == 1 ? 0.2f : 0.7f, 2);
          level2.push_back(0.05f);
        }
      }
    }
    const auto ground = label(s, level2).ground;
    std::vector<int> columns;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      if (s.cloud.ring[i] == 2 && ground[i] != 0) columns.push_back(s.cloud.column[i]);
    }
    return columns;
  };
  std::vector<int> all(60);
  for (int col = 0; col < 60; ++col) all[static_cast<std::size_t>(col)] = col;
  // No gap: nothing in the data says the terrain did not rise.
  CHECK(ring2_ground(-1) == all);
  // The road seen through the gap 12 m out: the fence top over the gap (ring 2 there climbs
  // 0.7 m within a metre of that road: steep, refused by the walk) and beside it are objects.
  std::vector<int> beside = all;
  beside.erase(beside.begin() + 29, beside.begin() + 32);
  CHECK(ring2_ground(30) == beside);
}

TEST_CASE("column profiles: past an obstacle, level with the ground before it is not enough",
          "[detector][profiles]") {
  // Sim hills_s2 (20 Hz): a car beside the vehicle hides rings 1-3; ring 4 passes over it
  // to a tree crown 24 m out, 0.5 m under the ground before the car and 3 m over the level-2
  // surface, fitted there to a valley floor the column never saw. Level with the ground
  // before it, it resumed past the car: the level-2 surface may be right.
  const std::vector<float> level2 = {0.f, 0.f, 0.f, 0.f, 3.f};
  CHECK(label(car_then(24.f, -0.5f, 2), level2).ground.back() == 0);
  // Level with the ground the vehicle stands on, it is that road going on past the car (a
  // levee whose level-2 cell lies on the fields below).
  CHECK(label(car_then(24.f, -0.05f, 1), level2).ground.back() == 1);
  // With nothing between, the same return goes on from the ground before it.
  Scan open;
  add(open, 0, 0, 6.f, 0.f, 1);
  add(open, 4, 0, 24.f, -0.5f, 1);
  CHECK(label(open, {0.f, 3.f}).ground == std::vector<std::uint8_t>{1, 1});
}
