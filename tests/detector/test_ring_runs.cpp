// Column profiles along the rings (docs/detector.md, "Column profiles", rules 5 and 7):
// silhouettes, a ring across the frame's edge, lines along walls, shadows.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <initializer_list>
#include <utility>
#include <vector>

#include "column_scan.hpp"

using namespace vlpground::detail;
using namespace column_scan;

namespace {
// Rings 0, 1, ... on ground at the given ranges, in columns [0, columns), the ground at
// range r height(r) high.
void add_ground_rings(Scan& s, std::initializer_list<float> ranges, int columns,
                      float (*height)(float)) {
  int ring = 0;
  for (const float r : ranges) {
    for (int col = 0; col < columns; ++col) add(s, ring, col, r, height(r), 1);
    ++ring;
  }
}

// The same on level ground (z = 0).
void add_level_rings(Scan& s, std::initializer_list<float> ranges, int columns) {
  add_ground_rings(s, ranges, columns, [](float) { return 0.f; });
}
}  // namespace

TEST_CASE("column profiles: a ring's ground across the shadow of an obstacle is ground",
          "[detector][profiles]") {
  // Past the box ring 4 is 1.6 m up at 20 m: over the allowance past an obstacle and too
  // steep a resume (0.08) for its column alone, but its ring runs on level from the ground
  // on both sides of the shadow.
  for (const float z : {1.6f, 2.1f}) {
    const Scan s = bowl_behind_box(z);
    const auto ground = label(s).ground;
    int shadow_ground = 0, shadow_returns = 0;
    for (std::size_t i = 0; i < s.cloud.size(); ++i) {
      if (s.cloud.ring[i] != 4 || s.cloud.column[i] < 20 || s.cloud.column[i] >= 40) continue;
      ++shadow_returns;
      shadow_ground += ground[i];
    }
    INFO("ring 4 past the box at z " << z);
    CHECK(shadow_returns == 20);
    // 0.5 m over the line joining the ground on both sides: standing on the bowl, not it.
    CHECK(shadow_ground == (z < 1.7f ? 20 : 0));
  }
}

TEST_CASE("column profiles: a shadow's ground cut short by a second object still anchors it",
          "[detector][profiles]") {
  // Ring 4 sees the hill before the box's shadow between a post and the shadow only, in two
  // columns (0.35 m of the ring, under shadow_anchor_m): hill_behind_box_and_post.
  enum Beside { kPost, kDropout };
  const auto shadow_ground = [](int open, Beside beside, const ProfileParams& p,
                                bool wall = false) {
    const Scan s = hill_behind_box_and_post(open, beside == kPost, wall);
    const auto ground =
        label_by_cell(s, {}, {}, std::vector<bool>(s.cloud.size(), false), nullptr, false, p)
            .ground;
    int n = 0;
    for (std::size_t i = 0; i < s.cloud.size(); ++i) {
      if (s.cloud.ring[i] == 4 && s.cloud.column[i] >= 18 && s.cloud.column[i] < 40) n += ground[i];
    }
    return n;
  };
  const ProfileParams defaults;
  CHECK(shadow_ground(2, kPost, defaults) == 22);
  ProfileParams off;
  off.shadow_anchor_cut_m = off.shadow_anchor_m;
  CHECK(shadow_ground(2, kPost, off) == 0);  // the rule off
  // No object cuts that ground short (ring 4 dropped out beside the box): a lone stretch on
  // a fence line anchors nothing.
  CHECK(shadow_ground(2, kDropout, defaults) == 0);
  // One open column: a single return, under shadow_anchor_cut_m.
  CHECK(shadow_ground(1, kPost, defaults) == 0);
  // With the ground seen over shadow_anchor_m the shadow is ground anyway.
  CHECK(shadow_ground(4, kDropout, defaults) == 22);
  // A wall's foot in the shadow instead: taken between ground seen over shadow_anchor_m only.
  CHECK(shadow_ground(4, kDropout, defaults, true) == 22);
  CHECK(shadow_ground(2, kPost, defaults, true) == 0);
}

TEST_CASE("column profiles: a ring grazing a levee's side under the vehicle's ground is ground",
          "[detector][profiles]") {
  // Ring 0 over 41 columns 1 degree apart runs down a levee's side from 0.2 m to 1.0 m
  // under the road (continuous along the ring), ring 1 beyond on the fields 2 m down. The
  // level-2 surface follows the side in columns 0-9 and 31-40 and is fitted to the fields
  // in between: there ring 0 is a single rise in its column (no raised neighbour, no ground
  // before it), but its ring runs on from ground to ground, on the line joining them.
  const auto grazing = [](float dz) {
    Scan s;
    for (int col = 0; col <= 40; ++col) {
      const float z = dz - 0.2f - 0.02f * static_cast<float>(col);
      add(s, 0, col, 8.f + 0.05f * static_cast<float>(col), z, 1);
    }
    for (int col = 0; col <= 40; ++col) add(s, 1, col, 17.f, -2.f, 1);
    std::vector<float> level2(s.cloud.size(), 0.f);
    for (std::size_t col = 10; col <= 30; ++col) level2[col] = s.cloud.z[col] + 2.f;
    const auto ground = label(s, level2).ground;
    int side = 0;
    for (std::size_t col = 10; col <= 30; ++col) side += ground[col];
    return side;
  };
  CHECK(grazing(0.f) == 21);
  // The same ring line 1.3 m higher, over the vehicle's ground: a ring line over a fence or a
  // box stays a single rise.
  CHECK(grazing(1.3f) == 0);
}

TEST_CASE("column profiles: the vehicle's road seen by two rings over a short stretch is ground",
          "[detector][profiles]") {
  // Sim embankment (seed 3, frame 4): the vehicle near a levee's edge; ring 0 meets the road
  // 7.3 m out only over 45 columns (5.5 m along the ring), passing over the edge to the
  // fields 1.9 m lower on both sides: a short run open to farther returns at both ends
  // (rule 5). Ring 1 goes on on the road 8.4 m out in the same columns, one run longer than
  // silhouette_max_m.
  enum Kind { kRoad, kRoadRing1Lower, kCrown, kLowObject };
  const auto scene = [](Kind kind) {
    Scan s;
    const bool crown = kind == kCrown;
    auto on_road = [&](int col) { return crown ? col >= 30 && col <= 38 : col >= 20 && col <= 64; };
    for (int col = 0; col <= 84; ++col) {
      if (!on_road(col)) add(s, 0, col, 14.f, -1.9f, 1);
      else if (crown) add(s, 0, col, 10.5f, 0.1f, 2);
      else if (kind == kLowObject) add(s, 0, col, 7.3f, 0.12f, 2);
      else add(s, 0, col, 7.3f, -0.03f, 1);
    }
    for (int col = 0; col <= 84; ++col) {
      if (!on_road(col)) add(s, 1, col, 16.5f, -1.9f, 1);
      else if (crown) add(s, 1, col, 11.7f, 0.15f, 2);
      else if (kind == kLowObject && col != 42) add(s, 1, col, 7.9f, 0.3f, 2);
      else add(s, 1, col, 8.4f, kind == kRoadRing1Lower ? -0.35f : -0.03f, 1);
    }
    const auto ground = label(s).ground;
    int kept = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      if (s.cloud.ring[i] == 0 && on_road(s.cloud.column[i])) kept += ground[i];
    }
    return kept;
  };
  CHECK(scene(kRoad) == 45);  // the road, going on level behind ring 0
  CHECK(scene(kRoadRing1Lower) == 0);  // ring 1 not level with it: nothing vouches for it
  // A tree crown in the fields level with the road (ring 0 at 10.5 m) is met again by ring
  // 1, which stands out as well; a low object level with the road, where ring 1 sees the
  // road behind it in one gap only (not over shadow_anchor_m of the ring): objects.
  CHECK(scene(kCrown) == 0);
  CHECK(scene(kLowObject) == 0);
}

TEST_CASE("column profiles: a rising ray passing on beside a face the next column met is an object",
          "[detector][profiles]") {
  // Sim bank_s101 (frame 4): rings 0-3 climb a bank face at 0.35; in columns 30-59 ring 4,
  // rising over the sensor, meets the face 2.5 m past ring 3; in columns 20-29 it passes on
  // and meets a bush on the bank's top 26 m out, far under the profile extrapolated up the
  // face (taken as the level top beyond the face); in columns 0-19 it goes to the sky. The
  // bush's run is short (4.5 m) and open to the sky on one side; on the other the same ray
  // met the face nearer, climbing more steeply than face_over_ray x the ray.
  const auto bush_ground = [](float face_z) {
    Scan s;
    add_bank_rings(s, 4, 60);
    const float ray = (1.925f - 1.8f) / 15.5f;  // ring 4's slope over the sensor (1.8 m)
    for (int col = 20; col < 60; ++col) {
      if (col < 30) add(s, 4, col, 26.f, 1.8f + ray * 26.f, 2);
      else add(s, 4, col, 15.5f, face_z, face_z < 3.f ? 1 : 2);
    }
    return ground_on_ring(s, label(s).ground, 4, 30);
  };
  CHECK(bush_ground(1.925f) == 0);  // the face going on at 0.35, the ray at 0.008
  // Where ring 4 met no ground nearer (a car roof 4 m up, refused as a step), nothing says
  // the terrain did not rise to meet the ray 26 m out.
  CHECK(bush_ground(4.f) == 10);
}

TEST_CASE("column profiles: a wider run far past the ring below against the sky is an object",
          "[detector][profiles]") {
  // Sim bank_s5901 (20 Hz, frame 1): rings up a bank face; the ring over them, rising over
  // the sensor, meets nothing but an object's top 6.1 m wide 38-42 m out, the sky on both
  // sides, its column's ring below on the bank 19 m out. Here rings 0-3 climb a face to
  // 13 m and ring 4 meets a run `columns` wide (1 degree each) `r` out, on a ray rising at
  // `ray`; `beside` puts a return farther out just before it (no sky there).
  constexpr int kFirst = 20;
  const auto object_ground = [](float r, int columns, float ray = 0.05f, bool beside = false,
                                bool car_below = false) {
    Scan s;
    add_bank_rings(s, 3, 60);
    for (int col = 0; col < 60; ++col) {  // ring 3 on the face, or on a car's roof 3.5 m up
      const bool car = car_below && col >= kFirst && col < kFirst + columns;
      add(s, 3, col, 13.f, car ? 3.5f : 1.05f, car ? 2 : 1);
    }
    if (beside) add(s, 4, kFirst - 1, r + 15.f, 1.8f + ray * (r + 15.f), 2);
    for (int col = kFirst; col < kFirst + columns; ++col) add(s, 4, col, r, 1.8f + ray * r, 2);
    return ground_on_ring(s, label(s).ground, 4, kFirst + columns);
  };
  CHECK(object_ground(25.f, 16) == 0);                // 6.5 m wide
  CHECK(object_ground(25.f, 21) == 21);               // 8.6 m wide: over wide_silhouette_max_m
  CHECK(object_ground(25.f, 16, 0.05f, true) == 16);  // no sky before it
  // 19 m out, not 1.5 times as far as the ring below (13 m): a hill's top against the sky.
  CHECK(object_ground(19.f, 22) == 22);
  // 55 m out (7 m wide): past wide_silhouette_range_m, the outline of far hills.
  CHECK(object_ground(55.f, 8) == 8);
  // Under the sensor.
  CHECK(object_ground(25.f, 16, -0.01f) == 16);
  // Where the ring below met no ground in its columns (a car's roof, refused as a step),
  // nothing says where the ground under the ray is.
  CHECK(object_ground(25.f, 16, 0.05f, false, true) == 16);
}

TEST_CASE("column profiles: a run around most of the turn never stands out",
          "[detector][profiles]") {
  // Fresh hills_s5902 tilted (frame 2): ring 2 meets the hillside 10-11 m out over 1672 of
  // the 1808 columns and, over the rest, straight ahead where the frame is cut, passes over
  // a crest to a valley 32-47 m out. Both ends of the near run open onto the farther valley
  // and lie 5 m apart across the gap: its chord is no extent, the run no object.
  const auto near_ground = [](int gap_columns) {
    Scan s;
    add_level_rings(s, {6.f, 8.f}, kColumns);
    const int half = gap_columns / 2;
    for (int col = 0; col < kColumns; ++col) {
      const bool valley = col < half || col >= kColumns - half;
      add(s, 2, col, valley ? 40.f : 10.f, valley ? -4.f : 0.f, 1);
    }
    const auto ground = label(s).ground;
    return ground_on_ring(s, ground, 2, kColumns - half) - ground_on_ring(s, ground, 2, half);
  };
  CHECK(near_ground(30) == kColumns - 30);  // the ends 5.3 m apart
  // A fragment of a rotation (10 columns, the frame cut there; crest_s5002 at Hi-Res): a
  // car 27 m out over 6 of them, farther ground on both sides, turns 5 degrees, not half a
  // turn, however many of the fragment's columns it covers.
  Scan s;
  add_level_rings(s, {6.f, 8.f}, 10);
  for (int col = 0; col < 10; ++col) {
    const bool car = col >= 2 && col <= 7;
    add(s, 2, col, car ? 27.f : 60.f, car ? -1.5f : -5.8f, car ? 2 : 1);
  }
  const auto ground = label(s).ground;
  CHECK(ground_on_ring(s, ground, 2, 8) - ground_on_ring(s, ground, 2, 2) == 0);
}

TEST_CASE("column profiles: a ring is a closed curve across the frame's edge",
          "[detector][profiles]") {
  // Sim slope (seed 2): a low object 35 m straight ahead, where the frame's edge cuts the
  // rotation, 0.8 m over ground that falls away past a grade change; ring 6 meets it over
  // columns 357-359 and 0-2 only, level enough with ring 5's road at 22.7 m for the walk to
  // take it, and passes on to ground 55 m out on both sides of it. Judged whole across the
  // edge, its run stands out (rule 5).
  const auto scan = [](bool object) {
    Scan s;
    const auto ahead = [](int col) { return col >= kColumns - 3 || col <= 2; };
    for (int ring = 4; ring <= 6; ++ring) {
      for (int col = 0; col < kColumns; ++col) {
        if (ring == 6 && object && ahead(col)) {
          add(s, ring, col, 35.f, 0.1f, 2);
        } else {
          const float r = ring == 4 ? 16.f : ring == 5 ? 22.7f : 55.f;
          add(s, ring, col, r, ring == 6 ? -1.f : 0.f, 1);
        }
      }
    }
    return s;
  };
  const Scan s = scan(true);
  const auto ground = label(s).ground;
  for (std::size_t i = 0; i < ground.size(); ++i) {
    INFO("ring " << s.cloud.ring[i] << " column " << s.cloud.column[i]);
    if (s.truth[i] == 2) CHECK(ground[i] == 0);
  }
  // A ring seen all around but for a gap behind (the vehicle's own body) has close ends
  // too: judged by the chord between them it would stand out; it covers more than half a
  // turn, so it does not.
  Scan ring0;
  for (int col = 0; col < kColumns; ++col) {
    if (col < 170 || col > 190) add(ring0, 0, col, 6.f, 0.f, 1);
  }
  const auto road = label(ring0).ground;
  int taken = 0;
  for (const std::uint8_t g : road) taken += g;
  CHECK(taken == static_cast<int>(road.size()));
}

TEST_CASE("column profiles: an object's face past a drop opens across the frame's edge",
          "[detector][profiles]") {
  // Sim slope_s4405 at 20 Hz: frames are cut straight ahead, where the road falls away past
  // a grade change. Rings 0-4 see the road to 15 m; ring 5 meets a box 32.6 m out, 1 m under
  // the road (columns 354-359, the frame's last), and across the edge a farther one (48 m
  // out, columns 0-2); the sky all around else. The box's run opens onto the sky at one end
  // and onto a return farther by more than the motion slack across the edge at the other:
  // it stands out (rule 5).
  struct Box {
    float z = -1.f;        // under the road (z = 0): seen past a drop
    float recede_m = 0.f;  // range added at each column: 0 is one face at one range
    float across_z = -2.4f;       // the return across the edge, 48 m out
    bool terrain_before = false;  // ring 5 meets terrain 48 m out up to 2 columns before
  };
  const auto box_ground = [](Box box) {
    Scan s;
    add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f}, kColumns);
    for (int col = 0; col < kColumns; ++col) {
      if (col >= kColumns - 6) {
        add(s, 5, col, 32.6f + box.recede_m * static_cast<float>(col - (kColumns - 6)), box.z, 2);
      } else if (col <= 2) {
        add(s, 5, col, 48.f, box.across_z, 2);
      } else if (box.terrain_before && col < kColumns - 8) {
        add(s, 5, col, 48.f, -2.4f, 1);
      }
    }
    const auto ground = label(s).ground;
    // Ring 5's ground in the box's columns, the frame's last six.
    return ground_on_ring(s, ground, 5) - ground_on_ring(s, ground, 5, kColumns - 6);
  };
  CHECK(box_ground({}) == 0);
  // Level with the road, the sky past its other end and a farther, lower return across the
  // edge, the face is an object too (slope_s6701 at 20 Hz: falls_across_edge).
  CHECK(box_ground({.z = 0.f}) == 0);
  // ... but where the ring goes on to farther terrain 2 columns past its other end (no sky
  // between), the run is a crest's top met by one ring straight ahead (hills_s2803): ground.
  CHECK(box_ground({.z = 0.f, .terrain_before = true}) == 6);
  // ... and where the return across the edge lies higher, ground.
  CHECK(box_ground({.z = 0.f, .across_z = 0.3f}) == 6);
  // Receding along the ring (0.8 m a column, within the run gap of each other), it is terrain
  // met sideways: a valley's floor past a drop (hills_s1805 at 20 Hz), ground, level or not.
  CHECK(box_ground({.recede_m = 0.8f}) == 6);
  CHECK(box_ground({.z = 0.f, .recede_m = 0.8f}) == 6);
}

TEST_CASE("column profiles: a frame fragment's end does not fall away across its edge",
          "[detector][profiles]") {
  // A capture's last frame, 20 columns of a rotation (1 degree apart): its ends, 19 degrees
  // apart, are within 1.5 column steps of a whole turn over 20 columns (18 degrees), so the
  // azimuth test takes them for neighbours; falls_across_edge asks for a whole rotation. Sim
  // slope_s5601 at 20 Hz, the last frame (36 columns): ring 4 sees the road 18 m out at its
  // last two columns, the sky before them, and an object 38 m out at its first column.
  Scan s;
  add_level_rings(s, {3.f, 4.f, 5.f, 6.f, 7.f}, 20);
  for (int col = 0; col < 20; ++col) {
    if (col <= 2) add(s, 5, col, 38.f, -2.6f, 2);
    if (col >= 17) add(s, 5, col, 10.f, 0.f, 1);
  }
  const auto ground = label(s).ground;
  // The road at the last columns does not open across the edge onto the farther, lower
  // return (falls_across_edge): ground.
  CHECK(ground_on_ring(s, ground, 5) - ground_on_ring(s, ground, 5, 17) == 3);
}

TEST_CASE("column profiles: an object a gap cut in two stands out whole",
          "[detector][profiles]") {
  // Sim hills_s102 (frame 2): past a crest, ring 6 meets a low object 33-34 m out whose
  // edge steps back 1.4 m at a dropped column; the ground beside it fell out of reach (no
  // return: the sky). Its nearer part (columns 24-26) stands out, the sky on one side and
  // the farther part on the other; the farther part (columns 20-22) meets the sky on one
  // side and the nearer part on the other. Together they are one short object.
  const auto scan = [](int near_last_col) {
    Scan s;
    const float r[] = {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f};
    for (int ring = 0; ring < 6; ++ring) {
      for (int col = 0; col <= 60; ++col) add(s, ring, col, r[ring], 0.3f - 0.01f * r[ring], 1);
    }
    for (int col = 20; col <= 22; ++col) add(s, 6, col, 34.f, 0.08f, 2);
    for (int col = 24; col <= near_last_col; ++col) add(s, 6, col, 32.7f, 0.11f, 2);
    return s;
  };
  // The level-2 surface lies 1 m under the farther part (the terrain seen elsewhere falls
  // away there), or on it (`on_terrain`: a ring's drop-out on dark ground beside a car).
  const auto ring6_ground = [](const Scan& s, bool on_terrain = false) {
    std::vector<float> level2(s.cloud.size(), 0.f);
    for (std::size_t i = 0; i < level2.size(); ++i) {
      if (s.cloud.ring[i] == 6 && s.cloud.column[i] <= 22 && !on_terrain) level2[i] = 1.f;
    }
    const auto ground = label(s, level2).ground;
    int far = 0, near = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      if (s.cloud.ring[i] != 6) continue;
      (s.cloud.column[i] <= 22 ? far : near) += ground[i];
    }
    return std::pair{far, near};
  };
  CHECK(ring6_ground(scan(26)) == std::pair{0, 0});
  // Where the level-2 surface agrees with the farther part, the sky beside it may be a
  // drop-out of the ground: the farther part stays ground.
  CHECK(ring6_ground(scan(26), true) == std::pair{3, 0});
  // Where the nearer part runs on (ground seen along 36 columns) it does not stand out: it
  // hides where the farther part ends, and nothing is said of that part.
  CHECK(ring6_ground(scan(60)) == std::pair{3, 37});
}

TEST_CASE("column profiles: a ring's line running on from high on a wall is that wall",
          "[detector][profiles]") {
  // Sim bank_s101 (Hi-Res, frame 4): rings 0-3 climb a bank face at 0.35; ring 4 runs along
  // a shed on the bank's top 16 m out. In columns 20-39 ring 3 meets the shed's face too,
  // 0.6 m under ring 4 (ring 4 is high on the face); in columns 0-19 ring 3 meets the bank
  // and ring 4, level with its hits on the face, is a gentle bend of the profile up the
  // bank. Continuous along the ring with the face and level with it, it is the shed.
  const auto scan = [](float far_z, float face_low_z = 1.3f) {
    Scan s;
    add_bank_rings(s, 3, 40);
    for (int col = 0; col < 40; ++col) {
      add(s, 3, col, col < 20 ? 13.f : 16.f, col < 20 ? 1.05f : face_low_z, col < 20 ? 1 : 2);
    }
    for (int col = 0; col < 40; ++col) add(s, 4, col, 16.f, col < 20 ? far_z : 1.9f, 2);
    return s;
  };
  const auto ring4_ground = [](const Scan& s) { return ground_on_ring(s, label(s).ground, 4, 20); };
  CHECK(ring4_ground(scan(1.9f)) == 0);
  // Sim bank_s105 at Hi-Res (rings 1.33 degrees apart): ring 3 meets the face only 0.45 m
  // under ring 4, itself an obstacle on the face: ring 4 is high on a face two rings tall.
  CHECK(ring4_ground(scan(1.9f, 1.45f)) == 0);
  // Ring 4 leaving the face downwards (0.3 m under its last hit high on it) is not the
  // wall's line going on: the bend up the bank stays ground.
  CHECK(ring4_ground(scan(1.6f)) == 20);
}

TEST_CASE("column profiles: a wall's line runs on across its returns that are not steep",
          "[detector][profiles]") {
  // As in sim bank_s4804 at Hi-Res: ring 4 runs along an object 16 m out on a bank's top. In
  // columns 20-39 ring 3 meets the object's face too, itself an obstacle 0.6 m under ring 4: the
  // face is two rings tall. In columns 10-19 ring 3 lies on the bank 1 m nearer and 0.7 m lower:
  // ring 4's returns there are obstacles to the walk but not steep. In columns 0-9 ring 3 meets the
  // bank and ring 4, level with the face, bends the profile gently up the bank (ground to the
  // walk). The line crosses columns 10-19, level with the face and at its range, and takes columns
  // 0-9 as the object.
  const auto scan = [](float near_z) {
    Scan s;
    add_bank_rings(s, 3, 40);
    for (int col = 0; col < 40; ++col) {
      if (col < 10)
        add(s, 3, col, 13.f, 1.05f, 1);
      else if (col < 20)
        add(s, 3, col, 15.f, 1.2f, 1);
      else
        add(s, 3, col, 16.f, 1.3f, 2);
    }
    for (int col = 0; col < 40; ++col) add(s, 4, col, 16.f, col < 10 ? near_z : 1.9f, 2);
    return s;
  };
  const auto ring4_ground = [](const Scan& s) { return ground_on_ring(s, label(s).ground, 4, 10); };
  CHECK(ring4_ground(scan(1.9f)) == 0);
  // Past the crossing the line is level both ways: ground rising more than the band over
  // the face (an object's top at the bank's level, the bank rising on) stays ground, all
  // but the return next to the object's (9 of 10; none without the band both ways).
  CHECK(ring4_ground(scan(2.2f)) == 9);
}

TEST_CASE("column profiles: over the sensor a run goes on across two dropped columns",
          "[detector][profiles]") {
  // Sim bank_s5 (tilted mounting): rings 0-3 climb a bank face at 0.35; ring 4 meets a tree
  // crown on the bank's top over columns 20-29, with the sky on both sides, and drops
  // columns 24-25 (foliage). Taken by the walk as the top's ground (a shoulder), the crown is
  // one short run open to the sky at both ends over the sensor: it stands out whole. Under
  // the sensor two dropped columns still cut a ring's run (real rings drop out on dark
  // asphalt), so the same line 0.1 m under the sensor keeps its labels.
  const auto crown_ground = [](float z) {
    Scan s;
    add_bank_rings(s, 4, 60);
    for (int col = 20; col < 30; ++col) {
      if (col != 24 && col != 25) add(s, 4, col, 22.f, z, 2);
    }
    return ground_on_ring(s, label(s, std::vector<float>(s.cloud.size(), 0.f)).ground, 4);
  };
  CHECK(crown_ground(2.6f) == 0);
  CHECK(crown_ground(1.7f) == 8);
}

TEST_CASE("column profiles: the vehicle's road behind an object's foot is ground",
          "[detector][profiles]") {
  // Sim embankment_s1502 at 5 Hz (frame 1): ring 0 meets the road all along; ring 1 runs
  // along a parked car's foot, steps back past its corner onto the road's edge, level with
  // ring 0's road, over 1.7 m, then passes over the edge to the fields 2.9 m lower. The
  // car and the road are one run along the ring (the step within the run gap), short and
  // open at both ends: it stood out whole (rule 5) and the road's edge was lost. Ranges
  // are scaled to the scan's 1-degree columns (a step back 3 times the distance across the
  // rays, within the run gap, lies within 9 m).
  struct Scene {
    float road_r = 3.5f;     // the road's range on the ring
    float corner_r = 3.16f;  // the car's foot where the ring leaves it
    int road_end = 49;       // the road's last column on the ring
    float road_step = 0.f;   // how much farther each of its columns is than the one before
    int low_start = 0;       // columns 10 to low_start - 1 of the car: low, nothing over them
    // The ring is ring 0, the column's first return (embankment_s2302 dual: the car beside
    // the vehicle), not ring 1 over ring 0's road.
    bool lowest = false;
    float road_behind_min_m = ProfileParams{}.road_behind_min_m;
    float road_z = -0.08f;  // the height of the ring's road part (ring 0's road: -0.08 m)
  };
  const auto road_ground = [](const Scene& scene) {
    Scan s;
    const int ring = scene.lowest ? 0 : 1;
    if (!scene.lowest) {
      for (int col = 0; col <= 84; ++col) add(s, 0, col, scene.road_r - 0.9f, -0.08f, 1);
    }
    for (int col = 0; col <= 84; ++col) {
      if (col < 10) {
        add(s, ring, col, scene.road_r, -0.08f, 1);  // the road before the car
      } else if (col < 30) {                         // the car's foot, coming out to its corner
        const float t = static_cast<float>(col - 10) / 19.f;
        const float z = col < scene.low_start ? -0.06f : 0.15f - 0.15f * t;
        const float foot_r = scene.road_r - 0.6f;
        add(s, ring, col, foot_r + t * (scene.corner_r - foot_r), z, 2);
      } else if (col <= scene.road_end) {
        add(s, ring, col, scene.road_r + scene.road_step * static_cast<float>(col - 30),
            scene.road_z, 1);
      } else {
        add(s, ring, col, 20.7f, -2.93f, 1);  // the fields
      }
    }
    for (int col = scene.low_start > 0 ? scene.low_start : 10; col <= 84; ++col) {
      if (col < 30) {  // the car's side over its foot, then the fields
        add(s, ring + 1, col, scene.road_r - 0.6f, 0.4f, 2);
      } else {
        add(s, ring + 1, col, 24.6f, -2.93f, 1);
      }
    }
    for (int col = std::max(10, scene.low_start); col < 30; ++col) {
      add(s, ring + 2, col, scene.road_r - 0.6f, 0.7f, 2);
    }
    ProfileParams params;
    params.road_behind_min_m = scene.road_behind_min_m;
    const auto ground =
        label_by_cell(s, {}, {}, std::vector<bool>(s.cloud.size(), false), nullptr, false, params)
            .ground;
    int n = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      const int col = s.cloud.column[i];
      if (s.cloud.ring[i] == ring && col >= 30 && col <= scene.road_end) n += ground[i];
    }
    return n;
  };
  CHECK(road_ground({}) == 20);
  CHECK(road_ground({.lowest = true}) == 20);
  // The ring going on smoothly from the object (no step back past an edge): the object's
  // own surface, level with the road past the road's edge (embankment_s2204 tilted: a bush
  // on the levee's side), stands out with it.
  CHECK(road_ground({.corner_r = 3.45f}) == 0);
  // A step back of 0.15 m over 0.06 m across (the surface joining them more than 18 degrees
  // off the rays): an oblique face seen by columns far apart (a wall's foot at 20 Hz), no
  // edge; 0.23 m over as much is one (a car's foot stepping in and out, embankment_s2905:
  // 0.12 m over 0.03 m).
  CHECK(road_ground({.corner_r = 3.35f}) == 0);
  CHECK(road_ground({.corner_r = 3.27f}) == 20);
  // The ring stepping on past the edge as far again at every column: a surface running
  // along the rays (a car's side seen end-on, level with the road: hills_s3101), no edge.
  CHECK(road_ground({.road_end = 35, .road_step = 0.34f}) == 0);
  // Close in, a step back within 18 degrees of the rays but under edge_step_min_m (0.12 m):
  // range noise along an oblique wall's foot (embankment_s2005 at 5 Hz: 0.07 m over 0.02 m
  // across; a low fence's foot at 5 Hz, fences_s1702: 0.10-0.12 m), no edge; 0.13 m is one (a
  // car's foot ending 0.13 m short of the ring's road, embankment_s2205 tilted).
  CHECK(road_ground({.road_r = 1.4f, .corner_r = 1.3f, .road_end = 70}) == 0);
  CHECK(road_ground({.road_r = 1.4f, .corner_r = 1.27f, .road_end = 70}) == 41);
  // The road's part shorter than road_behind_min_m (0.4 m): nothing vouches for it; 0.43 m
  // does (embankment_s2604: 0.43 m of road between a car's corner and the levee's edge).
  CHECK(road_ground({.road_end = 36}) == 0);
  CHECK(road_ground({.road_end = 37}) == 8);
  // ... nor one spanning under road_behind_min_rad (0.04) of the ring, however long it is
  // (here with road_behind_min_m at 0.1 m): 2 degrees no, 3 degrees yes.
  CHECK(road_ground({.road_end = 32, .road_behind_min_m = 0.1f}) == 0);
  CHECK(road_ground({.road_end = 33, .road_behind_min_m = 0.1f}) == 4);
  // The object's low end, level with the road and nothing over it, taken by the walk: the
  // object is still in front of the road.
  CHECK(road_ground({.low_start = 14}) == 20);
  // The road part 0.1 m over the road it goes on from: still the vehicle's road by the
  // walk's measure (0.15 m).
  CHECK(road_ground({.road_z = 0.02f}) == 20);
  // Nothing of the run refused by the walk (the whole foot low, nothing over it:
  // embankment_s1502 at 20 Hz): the road part is kept only level with the road it goes on
  // from within whole_run_level_m (0.05 m), not 0.1 m over it (a low fence's line going on
  // from the road, fences_s1502 at 5 Hz).
  CHECK(road_ground({.low_start = 30}) == 20);
  CHECK(road_ground({.low_start = 30, .road_z = 0.02f}) == 0);
}

TEST_CASE("column profiles: the vehicle's road seen through gaps in an object's foot is ground",
          "[detector][profiles]") {
  // Sim embankment_s3401 tilted (frame 4): ring 3 runs along a car's ragged foot 9.3-9.4 m
  // out and sees the road 9.8 m out, level with ring 2's, through two gaps in it, one
  // column each. The car, gaps and all, is one short run along the ring (the steps within
  // the run gap), open at both ends: it stood out whole (rule 5) and took the road with it.
  // Here ring 1 along a car's foot 3.2 m out, the road 3.5 m out.
  struct Gap {
    float r = 3.5f;        // the gap's return: the road past the foot
    float z = -0.08f;      // level with ring 0's road
    int last = 20;         // the gaps: the even columns from 20 to last (20 to 40: the car)
    float foot_b = 3.2f;   // the foot's range in columns 23, 27, 31, ... (the others: 3.2 m)
    float lower_r = 2.6f;  // ring 0's road, which the gaps' road goes on from
    bool lowest = false;   // no ring 0: ring 1 is its columns' first return
  };
  const auto gap_ground = [](const Gap& gap) {
    Scan s;
    for (int col = 0; col <= 84 && !gap.lowest; ++col) add(s, 0, col, gap.lower_r, -0.08f, 1);
    for (int col = 0; col <= 84; ++col) {
      if (col < 20 || col > 40) {
        add(s, 1, col, 20.7f, -2.93f, 1);  // the fields past the levee's edge
      } else if (col <= gap.last && col % 2 == 0) {
        add(s, 1, col, gap.r, gap.z, 1);  // the road through the foot's gaps
      } else {
        add(s, 1, col, col % 4 == 3 ? gap.foot_b : 3.2f, 0.1f, 2);  // the car's foot
      }
    }
    for (int col = 0; col <= 84; ++col) {  // the car's side; the road through its gaps
      const bool car = col >= 20 && col <= 40, through = car && col <= gap.last && col % 2 == 0;
      if (through) {
        add(s, 2, col, 4.6f, -0.08f, 1);
      } else {
        add(s, 2, col, car ? 3.2f : 24.6f, car ? 0.4f : -2.93f, car ? 2 : 1);
      }
    }
    for (int col = 20; col <= 40; ++col) add(s, 3, col, 3.2f, 0.7f, 2);
    const auto ground = label(s).ground;
    int n = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      const int col = s.cloud.column[i];
      if (s.cloud.ring[i] == 1 && col > 20 && col <= 40 && col % 2 == 0) n += ground[i];
    }
    return n;
  };
  CHECK(gap_ground({.last = 28}) == 4);  // columns 22, 24, 26, 28
  // Level with the road within whole_run_level_m (0.05 m), not 0.1 m over it: a return
  // through a gap in a low fence, on something behind it.
  CHECK(gap_ground({.z = 0.02f, .last = 28}) == 0);
  // The ring stepping back onto it by under edge_step_min_m (0.12 m): the foot's own range
  // noise.
  CHECK(gap_ground({.r = 3.3f, .last = 28}) == 0);
  // The ring stepping back onto it on one side only, the foot 0.05 m nearer on the other:
  // not a gap in the object.
  CHECK(gap_ground({.last = 28, .foot_b = 3.45f}) == 0);
  // Going on from ring 0's road 2.1 m nearer, over gap_road_reach_m (2 m): the road's edge
  // may lie between the two rings (a bush's top over the fields, embankment_s1205 tilted);
  // 1.9 m is within it.
  CHECK(gap_ground({.last = 28, .lower_r = 1.4f}) == 0);
  CHECK(gap_ground({.last = 28, .lower_r = 1.6f}) == 4);
  // The lowest ring on the foot (embankment_s6003 at 5 Hz: ring 0 on a car's foot 6.5 m out
  // at the lane's edge, the road 6.9 m out through its gaps): the road through the gaps is
  // the column's first return, level with the vehicle's ground within whole_run_level_m,
  // not 0.08 m over it.
  CHECK(gap_ground({.z = -0.03f, .last = 28, .lowest = true}) == 4);
  CHECK(gap_ground({.z = 0.08f, .last = 28, .lowest = true}) == 0);
}

TEST_CASE("column profiles: the vehicle's road seen by any two consecutive rings is ground",
          "[detector][profiles]") {
  // Sim embankment_s304 (frame 1): behind the vehicle rings 0, 1 and 3 run on along the
  // road, ring 2 meets it only over a short stretch between the kerbs' ends (here: between
  // drop-outs), a short run open at both ends (rule 5). Ring 3 goes on level behind ring 2
  // in the same columns, nothing between: the road going on, as for a column's first two
  // ground returns.
  const auto kept = [](float ring3_z) {
    Scan s;
    for (int col = 0; col <= 84; ++col) add(s, 0, col, 6.9f, 0.f, 1);
    for (int col = 0; col <= 84; ++col) add(s, 1, col, 7.95f, 0.f, 1);
    for (int col = 30; col <= 50; ++col) add(s, 2, col, 9.4f, 0.f, 1);
    for (int col = 0; col <= 84; ++col) add(s, 3, col, 11.6f, ring3_z, 1);
    const auto ground = label(s).ground;
    int n = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) n += s.cloud.ring[i] == 2 ? ground[i] : 0;
    return n;
  };
  CHECK(kept(0.f) == 21);
  CHECK(kept(-0.35f) == 0);  // ring 3 not level with it: nothing vouches for ring 2
}

namespace {

// The returns of `s` in columns [0, end), in the cloud's order (by ring, then column): with
// `end` short of the scan's columns, a capture's last frame, a fragment of the rotation after
// the scan's, cut by the end of the data.
Scan in_cloud_order(const Scan& s, int end = kColumns) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < s.cloud.size(); ++i) {
    if (s.cloud.column[i] < end) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return s.cloud.ring[a] != s.cloud.ring[b] ? s.cloud.ring[a] < s.cloud.ring[b]
                                              : s.cloud.column[a] < s.cloud.column[b];
  });
  Scan out;
  for (const std::size_t i : order) {
    add(out, s.cloud.ring[i], s.cloud.column[i], s.cloud.range_xy[i], s.cloud.z[i], s.truth[i]);
  }
  return out;
}

// Labels `scan` after `before` with one ColumnProfiles, the scan going on from it when
// `continues`; no level-2 surface (the ring runs alone decide on the crate).
Labels label_after(const Scan& before, const Scan& scan, bool continues) {
  ColumnProfiles profiles;
  const auto none = [](const Scan& s) { return std::vector<float>(s.cloud.size(), std::nanf("")); };
  label_by_cell(before, none(before), none(before), std::vector<bool>(before.cloud.size(), false),
                &profiles);
  return label_by_cell(scan, none(scan), none(scan), std::vector<bool>(scan.cloud.size(), false),
                       &profiles, continues);
}

// How many of the crate's returns (ring 11, columns from 200) the fragment labels ground.
int crate_ground(const Scan& fragment, const Labels& labels) {
  int ground = 0;
  for (std::size_t i = 0; i < labels.ground.size(); ++i) {
    if (fragment.cloud.ring[i] == 11 && fragment.cloud.column[i] >= 200) ground += labels.ground[i];
  }
  return ground;
}

}  // namespace

TEST_CASE("column profiles: a run cut by the end of the data goes on in the frame before",
          "[detector][profiles]") {
  // make_scan's crate (ring 11, columns 200-205, 22.5 m out, the sky on both sides) stands
  // out in a whole rotation; a capture's last frame ending at column 203 cuts its run. Ring
  // 11 also meets a facade 30 m out in columns 0-10, so that the fragment's edge after the
  // crate is no sky: the ring has returns across it.
  Scan with_facade = make_scan();
  for (int col = 0; col <= 10; ++col) add(with_facade, 11, col, 30.f, 3.f, 2);
  const Scan whole = in_cloud_order(with_facade), fragment = in_cloud_order(with_facade, 203);
  REQUIRE(crate_ground(fragment, label_after(whole, fragment, false)) == 3);  // nothing beyond
  const Labels labels = label_after(whole, fragment, true);
  CHECK(crate_ground(fragment, labels) == 0);  // beyond the end, in the frame before: the sky
  // The road and the rings under the crate stay as they were (their runs are long).
  const Labels alone = label_after(whole, fragment, false);
  int changed = 0;
  for (std::size_t i = 0; i < labels.ground.size(); ++i) {
    const bool crate = fragment.cloud.ring[i] == 11 && fragment.cloud.column[i] >= 200;
    changed += !crate && labels.ground[i] != alone.ground[i];
  }
  CHECK(changed == 0);

  SECTION("an object longer than a silhouette in the frame before stays as the walk took it") {
    Scan longer = with_facade;
    for (int col = 206; col <= 220; ++col) add(longer, 11, col, 22.5f, 0.35f, 2);  // 8 m
    CHECK(crate_ground(fragment, label_after(in_cloud_order(longer), fragment, true)) == 3);
  }
  SECTION("nor is it joined to a return of the frame before that is not continuous with it") {
    Scan farther;
    for (std::size_t i = 0; i < with_facade.cloud.size(); ++i) {
      const bool crate = with_facade.cloud.ring[i] == 11 && with_facade.cloud.column[i] >= 200;
      add(farther, with_facade.cloud.ring[i], with_facade.cloud.column[i],
          crate ? 30.f : with_facade.cloud.range_xy[i], crate ? 0.f : with_facade.cloud.z[i],
          with_facade.truth[i]);
    }
    CHECK(crate_ground(fragment, label_after(in_cloud_order(farther), fragment, true)) == 3);
  }
}

TEST_CASE("column profiles: a short run hidden at one end by an object in front stands out",
          "[detector][profiles]") {
  // Sim slope_s1201 at 20 Hz (frame 2): ring 6 meets a box 30.8 m out, 0.24 m over the
  // vehicle's plateau, past a grade change where the slope falls away: the sky before it,
  // and after it a nearer box 16 m out (standing out), past which the ring lands 60 m out.
  // Rings 0-5 see the plateau level to 20 m.
  struct Ring6 {
    float far_z = 0.24f;  // the far box's top
    float past_r = 60.f;  // where the ring lands past the near box
    float past_z = -2.f;
    int edge_returns = 0;  // returns 25 m out, level with the vehicle's ground, after the far box
    int level_past_box = 0;  // columns of level ground 29 m out right past the near box
    int sky_past_box = 0;    // columns without a return after those, before past_r
    // Past the far box's open end (columns [beyond_from, beyond_to], beyond_r out): an
    // object, the fields or the road going on, this high (none when NaN).
    float beyond_z = std::nanf("");
    float beyond_r = 60.f;
    int beyond_from = 8;
    int beyond_to = 11;
    bool beyond_face = false;  // ring 7 over them at their range: a face
    float far_step_m = 0.f;    // the far box's range grows by this per column towards column 15
  };
  const auto far_box_ground = [](const Ring6& ring6) {
    Scan s;
    add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61);
    for (int col = ring6.beyond_from; col <= ring6.beyond_to && !std::isnan(ring6.beyond_z);
         ++col) {
      add(s, 6, col, ring6.beyond_r, ring6.beyond_z, 2);
      if (ring6.beyond_face) add(s, 7, col, ring6.beyond_r, ring6.beyond_z + 1.f, 2);
    }
    const int far_end = 22 - ring6.edge_returns;
    for (int col = 15; col <= far_end; ++col) {
      add(s, 6, col, 30.8f + ring6.far_step_m * static_cast<float>(far_end - col), ring6.far_z, 2);
    }
    for (int col = far_end + 1; col <= 22; ++col) add(s, 6, col, 25.f, 0.f, 2);
    for (int col = 24; col <= 38; ++col) add(s, 6, col, 16.f, 1.f, 2);
    const int level_end = 39 + ring6.level_past_box;
    for (int col = 39; col < level_end; ++col) add(s, 6, col, 29.f, 0.f, 1);
    for (int col = level_end + ring6.sky_past_box; col <= 60; ++col) {
      add(s, 6, col, ring6.past_r, ring6.past_z, 1);
    }
    // The level-2 surface at z = 0. Ring 6's ground from column 12 on (past beyond_z's).
    const auto ground = label(s, s.cloud.z).ground;
    return ground_on_ring(s, ground, 6, far_end + 1) - ground_on_ring(s, ground, 6, 12);
  };
  CHECK(far_box_ground({}) == 0);
  // A lone return between the boxes (a pixel on the far box's edge, slope_s2405) that lies
  // level with the vehicle's ground stands out too, and hides the far box in turn; two
  // such returns are a run of road between them, which stays, and the far box with it.
  CHECK(far_box_ground({.edge_returns = 1}) == 0);
  CHECK(far_box_ground({.edge_returns = 2}) == 6);
  // The ring comes out behind the near box where it went in: terrain passing behind a tree
  // trunk (hills_s1802 at 20 Hz), which the trunk only hides.
  CHECK(far_box_ground({.past_r = 30.9f, .past_z = 0.25f}) == 8);
  // Only while still passing the object: where the ring goes to the sky past the near box
  // first, it did not come out there, whatever it meets beyond (crest_s1001 tilted: ring 5
  // on an object 35 m out past a crest, beside a nearer object 16 m out; past that one the
  // sky, then another object at 19 m).
  CHECK(far_box_ground({.past_r = 30.9f, .past_z = 0.25f, .sky_past_box = 5}) == 0);
  // A drop-out (fewer columns than the sky takes) is not the sky: the ring came out there.
  CHECK(far_box_ground({.past_r = 30.9f, .past_z = 0.25f, .sky_past_box = 2}) == 8);
  // Past the object the ring ran on over level ground first: the sky after that says
  // nothing of the far box, and the ring came out where it went in (hills_s5 at 20 Hz).
  CHECK(far_box_ground(
            {.past_r = 30.9f, .past_z = 0.25f, .level_past_box = 14, .sky_past_box = 4}) == 8);
  // Level with the ground under the vehicle: the road between two parked cars (jam), the
  // ring going on along the road past the farther car's end (2 road returns counted too).
  CHECK(far_box_ground({.far_z = 0.05f,
                        .beyond_z = 0.f,
                        .beyond_r = 33.f,
                        .beyond_from = 0,
                        .beyond_to = 13}) == 10);
  // ... unless past its open end the ring meets an object far under it (standing out: 4 m
  // wide, the sky at both ends): the terrain falls away there, out of the ring's reach, and
  // the level run is an object's face (slope_s6103: a van 36.8 m out past a grade change).
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = -2.f}) == 0);
  // Over the run's level (a drop of no more than drop_m) the ring does not fall away.
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = -0.4f}) == 8);
  // The fields far below a road on an embankment, past a car on it: a long run taken as
  // ground (embankment_s901 tilted), which the road goes on to.
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = -2.f, .beyond_from = 0}) == 8);
  // A face there instead (ring 7 over it at its range), not taken as ground: an object, the
  // terrain under it lower still.
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = -2.f, .beyond_from = 0, .beyond_face = true}) ==
        0);
  // Past its open end, the sky over at least twice sky_columns and then the ring lower than
  // the run, however little: the terrain fell out of the ring's reach there, and a level run
  // at one range is an object's face (slope_s6603: ring 6 on an object 36 m out, 0.77 m over
  // the slope, the sky over 189 columns past it, then the slope 0.32 m lower 42 m out).
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = -0.4f, .beyond_from = 0, .beyond_to = 8}) == 0);
  // Not past a narrower sky (a drop-out), nor where the ring comes back higher ...
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = -0.4f, .beyond_from = 0, .beyond_to = 9}) == 8);
  CHECK(far_box_ground({.far_z = 0.05f, .beyond_z = 0.1f, .beyond_from = 0, .beyond_to = 8}) == 8);
  // ... nor where the run recedes towards the sky: the terrain falling away there itself,
  // seen by the ring to its edge (hills_s903 at 5 Hz: 33.8 -> 36.3 m out).
  CHECK(far_box_ground({.far_z = 0.05f,
                        .beyond_z = -0.4f,
                        .beyond_from = 0,
                        .beyond_to = 8,
                        .far_step_m = 0.25f}) == 8);
}

TEST_CASE("column profiles: a short ring line an object in front cuts in two stands out whole",
          "[detector][profiles]") {
  // Sim bank_s6401 tilted (frame 3): ring 9 meets an object 1.1 m tall 29-32 m out, cut by
  // a low object 16.9 m out (standing out), the sky on both sides. Here rings 0-5 see the
  // vehicle's plateau (or a hill climbing at 0.1) to 20 m; ring 6 meets the line in columns
  // `one_from`-18 and from the object's end to `two_end`, the object in front 16 m out in
  // 19-21 (`object_columns` from 19).
  struct Line {
    float r = 30.8f;
    float z = 0.24f;  // over level ground (on the hill: on it)
    bool hill = false;
    int two_end = 25;      // 25: 5.4 m long in all
    int one_from = 15;
    int object_columns = 3;
    int before_from = 15;  // the ring's returns `before_r` out from this column to 14
    float before_r = 34.f;
    int after_to = 0;  // ... and after `two_end` to this column
  };
  const auto line_ground = [](const Line& line) {
    const auto hill = [](float r) { return 0.1f * (r - 4.f); };
    Scan s;
    if (line.hill) {
      add_ground_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61, hill);
    } else {
      add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61);
    }
    const float z = line.hill ? hill(line.r) : line.z;
    for (int col = line.before_from; col < 15; ++col) add(s, 6, col, line.before_r, z, 2);
    for (int col = line.one_from; col <= 18; ++col) add(s, 6, col, line.r, z, 2);
    const int two_from = 19 + line.object_columns;
    for (int col = 19; col < two_from; ++col) add(s, 6, col, 16.f, z + 1.f, 2);
    for (int col = two_from; col <= line.two_end; ++col) add(s, 6, col, line.r, z, 2);
    for (int col = line.two_end + 1; col <= line.after_to; ++col) {
      add(s, 6, col, line.before_r, z, 2);
    }
    const auto ground = label(s, s.cloud.z).ground;  // the level-2 surface on every return
    return ground_on_ring(s, ground, 6, line.two_end + 1) - ground_on_ring(s, ground, 6, 15);
  };
  CHECK(line_ground({}) == 0);
  // Longer than a silhouette (8.6 m): the ring's line going on behind the object.
  CHECK(line_ground({.two_end = 30}) == 13);
  // Where the ring goes on farther at an end (2 m, not the sky), terrain may: between tree
  // trunks (hills_s803 tilted).
  CHECK(line_ground({.before_from = 0}) == 8);
  CHECK(line_ground({.after_to = 40}) == 8);
  // Level with the vehicle's ground: the road between parked cars (jam_s1003).
  CHECK(line_ground({.z = 0.05f}) == 8);
  // Over the sensor: an object far past the ring below's ground (37 m, ring 5's 20 m).
  CHECK(line_ground({.r = 37.f, .hill = true, .two_end = 24}) == 0);
  // Less than 1.5 times as far (28 m): a hill's top past a tree (hills_s501 tilted).
  CHECK(line_ground({.r = 28.f, .hill = true, .two_end = 24}) == 7);
  // Within wide_silhouette_range_m (50 m) only: past it, far hill tops against the sky
  // (bank_s5004 at 20 Hz, ring 9 76 m out). A line of 6 columns, 3.9 and 4.8 m long.
  Line narrow{.two_end = 22, .one_from = 17, .object_columns = 2};
  narrow.r = 45.f;
  CHECK(line_ground(narrow) == 0);
  narrow.r = 55.f;
  CHECK(line_ground(narrow) == 4);
}

TEST_CASE("column profiles: past an object, a speck before the sky at the ring's end hides",
          "[detector][profiles]") {
  // Sim slope_s6103 at 5 Hz (frame 1): ring 6 meets a van 36.8 m out past a grade change
  // (columns 13-20), beside a nearer box 30.2 m out (6-12, standing out), before which the
  // ring's first return (column 5) is a speck 34.9 m out on an edge, the sky before it
  // (the frame's edge). Past the van the sky, then the slope's objects 60 m out. Rings 0-5
  // see the vehicle's plateau to 20 m.
  struct Speck {
    bool second = false;         // a second return beside the speck, continuous with it
    bool return_before = false;  // a return 25 m out two columns before the speck
  };
  const auto van_ground = [](const Speck& speck) {
    Scan s;
    add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61);
    if (speck.return_before) add(s, 6, 2, 25.f, 0.6f, 2);
    if (speck.second) add(s, 6, 4, 34.9f, 0.11f, 2);
    add(s, 6, 5, 34.9f, 0.11f, 2);
    for (int col = 6; col <= 12; ++col) add(s, 6, col, 30.2f, 0.35f, 2);
    for (int col = 13; col <= 20; ++col) add(s, 6, col, 36.8f, 0.24f, 2);
    for (int col = 26; col <= 60; ++col) add(s, 6, col, 60.f, -2.f, 2);
    const auto ground = label(s, s.cloud.z).ground;  // the level-2 surface on every return
    return ground_on_ring(s, ground, 6, 21) - ground_on_ring(s, ground, 6, 13);  // the van
  };
  // Passing the box, the ring ends at the speck: it did not come out from behind the box.
  CHECK(van_ground({}) == 0);
  // Two returns going on there: the ring came out, the van's ground goes on behind the box.
  CHECK(van_ground({.second = true}) == 8);
  // Two columns without a return before the speck are a drop-out, not the sky.
  CHECK(van_ground({.return_before = true}) == 8);
}

TEST_CASE("column profiles: a chain of hidden runs stands out however long",
          "[detector][profiles]") {
  // Sim crest_s1001 tilted: an object's edge stepping back column by column, each step a
  // run of its own, between a nearer object (standing out) and a farther one past a
  // crest. Rings 0-5 see the vehicle's plateau to 20 m. Ring 6: the sky (columns 0-9), a
  // box 30.8 m out (10-16), `steps` returns each 0.9 m nearer than the one before (17 on),
  // a box 16 m out (standing out), then the ground 60 m out. Each step is hidden by the
  // one after it, the box 30.8 m out by the farthest step: a chain against the columns'
  // order.
  const auto far_box_ground = [](int steps) {
    Scan s;
    add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61);
    for (int col = 10; col <= 16; ++col) add(s, 6, col, 30.8f, 0.24f, 2);
    const int near_from = 17 + steps;
    for (int step = 0; step < steps; ++step) {
      add(s, 6, 17 + step, 16.f + 0.9f * static_cast<float>(steps - step), 1.f, 2);
    }
    for (int col = near_from; col < near_from + 12; ++col) add(s, 6, col, 16.f, 1.f, 2);
    for (int col = near_from + 12; col <= 60; ++col) add(s, 6, col, 60.f, -2.f, 1);
    return ground_on_ring(s, label(s, s.cloud.z).ground, 6, 17);
  };
  CHECK(far_box_ground(0) == 0);
  CHECK(far_box_ground(6) == 0);
  CHECK(far_box_ground(10) == 0);
}

TEST_CASE("column profiles: over the sensor, a hidden run stands out only at one range",
          "[detector][profiles]") {
  // Sim hills_s603 at 20 Hz (frame 1): the terrain climbs at 0.1 past the sensor's height.
  // Ring 6 meets an object 37 m out, the sky before it, and after it a nearer one 16 m out
  // (standing out), past which the ring lands on the hill 60 m out. Rings 0-5 see the climb
  // to 20 m; the level-2 surface lies on every return.
  const auto far_run_ground = [](float recede_per_column_m) {
    const auto hill = [](float r) { return 0.1f * (r - 4.f); };
    Scan s;
    add_ground_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61, hill);
    for (int col = 15; col <= 22; ++col) {
      const float r = 37.f + recede_per_column_m * static_cast<float>(col - 15);
      add(s, 6, col, r, hill(r), 2);
    }
    for (int col = 24; col <= 38; ++col) add(s, 6, col, 16.f, 2.5f, 2);
    for (int col = 39; col <= 60; ++col) add(s, 6, col, 60.f, hill(60.f), 1);
    return ground_on_ring(s, label(s, s.cloud.z).ground, 6, 23);
  };
  CHECK(far_run_ground(0.f) == 0);
  // Receding along the ring (2.1 m over the run, more than the run gap): the ring tracing
  // the hill sideways between two objects (bank_s1805 tilted), which stays ground.
  CHECK(far_run_ground(0.3f) == 8);
}

TEST_CASE("column profiles: a ring passing an object hiding a run follows it across the edge",
          "[detector][profiles]") {
  // Sim slope_s2703: frames are cut straight ahead, where cars stand one behind the other on
  // a ramp falling away out of the rings' reach. Rings 0-5 see the vehicle's plateau to
  // 20 m. Ring 6 meets a car 16 m out straight ahead (columns 357-359 and 0-5, one run
  // across the frame's edge, standing out), a car 30.8 m out beside it (columns 6-12, 0.24 m
  // over the plateau: the sky after it) and, past the near car before the edge, the ramp
  // 60 m out. Followed across the edge past the near car, the ring does not come out where
  // the far car's run went in behind it: the far car is hidden and stands out.
  const auto far_car_ground = [](float past_r, float past_z) {
    Scan s;
    add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, kColumns);
    for (int col = 0; col < kColumns; ++col) {
      if (col <= 5 || col >= 357) {
        add(s, 6, col, 16.f, 1.f, 2);
      } else if (col <= 12) {
        add(s, 6, col, 30.8f, 0.24f, 2);
      } else if (col >= 20) {
        add(s, 6, col, past_r, past_z, 1);
      }
    }
    const auto ground = label(s, s.cloud.z).ground;  // the level-2 surface at z = 0
    int far = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      const int col = s.cloud.column[i];
      far += s.cloud.ring[i] == 6 && col >= 6 && col <= 12 ? ground[i] : 0;
    }
    return far;
  };
  CHECK(far_car_ground(60.f, -2.f) == 0);
  // Coming out across the edge where the run went in (within twice the run gap, doubled
  // for the vehicle's motion over the rotation), the ring only passed behind the near car.
  CHECK(far_car_ground(33.f, 0.24f) == 7);
}

TEST_CASE("column profiles: past an object, nearer ground across the edge is not followed",
          "[detector][profiles]") {
  // Sim hills_s1902 at 20 Hz: ring 6 meets ground falling into a valley (columns 6-12,
  // 19.5 m out, 0.5 m under the plateau) behind a tree 14 m out (columns 3-5, standing
  // out); before the tree, and all around the rotation, the ring runs on nearer (17 m)
  // until the valley's far side 60 m out. The valley's floor is not hidden by the tree:
  // the ring past it is the hill's nearer side, not the object's, so the walk stops at the
  // frame's edge.
  Scan s;
  add_level_rings(s, {6.f, 8.f, 10.f, 12.f, 14.f, 16.f}, kColumns);
  for (int col = 0; col < kColumns; ++col) {
    if (col >= 3 && col <= 5) {
      add(s, 6, col, 14.f, 1.f, 2);
    } else if (col >= 6 && col <= 12) {
      add(s, 6, col, 19.5f, -0.5f, 1);
    } else if (col >= 13 && col <= 300) {
      add(s, 6, col, 60.f, -4.f, 1);
    } else {
      add(s, 6, col, 17.f, 0.f, 1);  // columns 0-2 and 301-359
    }
  }
  const auto ground = label(s, s.cloud.z).ground;
  int valley = 0;
  for (std::size_t i = 0; i < ground.size(); ++i) {
    const int col = s.cloud.column[i];
    valley += s.cloud.ring[i] == 6 && col >= 6 && col <= 12 ? ground[i] : 0;
  }
  CHECK(valley == 7);
}

TEST_CASE("column profiles: a ring line small cuts broke into parts stands out whole",
          "[detector][profiles]") {
  // Sim hills_s2104 (frame 1): past a crest, ring 6 meets a tree crown 27 m out, level with
  // the vehicle's ground and 2.3 m over the valley floor the rings never see; its foliage
  // drops columns, so its ring line comes in parts that neither meet the sky where cut nor
  // stand out alone. Rings 0-5 see the plateau level to 20 m.
  struct Crown {
    float step_in_m = 0.f;      // each part nearer than the one before by this (stairs)
    int dropped = 2;            // columns dropped at each cut
    float over_level2 = 2.3f;   // the crown's height over the level-2 surface
    bool nearer_after = false;  // the ring goes on nearer past the crown, not to the sky
    enum { kSky, kFace, kLevel, kFarther } above = kSky;  // ring 7 in the crown's columns
    // Ring 6 past the sky at the line's ends (`past_sky` columns without a return, on one
    // side or both): 5 returns this far out and this high (none when NaN).
    float past_r = std::nanf("");
    float past_z = 0.f;
    int past_sky = 3;
    bool past_both = true;
  };
  const auto crown_ground = [](const Crown& crown) {
    Scan s;
    add_level_rings(s, {6.f, 8.f, 10.f, 12.5f, 15.f, 20.f}, 61);
    // Ring 6 past the sky before the crown, in column order as a scan gives them.
    for (int n = 0; n < 5 && !std::isnan(crown.past_r); ++n) {
      add(s, 6, 15 - crown.past_sky + n, crown.past_r, crown.past_z, 1);
    }
    int col = 20;  // the crown 0.1 m over the ground ring 5 meets: three parts of 3 columns
    for (int part = 0; part < 3; ++part, col += crown.dropped) {
      const float range = 27.f - crown.step_in_m * static_cast<float>(part);
      for (int n = 0; n < 3; ++n, ++col) add(s, 6, col, range, 0.1f, 2);
    }
    const int crown_last = col - crown.dropped - 1;
    for (int n = 0; n < 5 && !std::isnan(crown.past_r) && crown.past_both; ++n) {
      add(s, 6, crown_last + 1 + crown.past_sky + n, crown.past_r, crown.past_z, 1);
    }
    if (crown.nearer_after) {
      for (col = crown_last + 2; col <= 60; ++col) add(s, 6, col, 20.f, 0.1f, 1);
    }
    for (col = 20; col <= crown_last && crown.above != Crown::kSky; ++col) {
      if (crown.above == Crown::kFace) add(s, 7, col, 27.f, 1.1f, 2);      // the crown over it
      if (crown.above == Crown::kLevel) add(s, 7, col, 27.1f, 0.1f, 2);    // level, no face
      if (crown.above == Crown::kFarther) add(s, 7, col, 45.f, -0.3f, 1);  // ground farther
    }
    std::vector<float> level2(s.cloud.size(), 0.f);
    for (std::size_t i = 0; i < level2.size(); ++i) {
      if (s.cloud.ring[i] == 6) level2[i] = crown.over_level2;
    }
    const auto ground = label(s, level2).ground;
    int taken = 0;
    for (std::size_t i = 0; i < ground.size(); ++i) {
      const int c = s.cloud.column[i];
      taken += s.cloud.ring[i] == 6 && c >= 20 && c <= crown_last ? ground[i] : 0;
    }
    return taken;
  };
  CHECK(crown_ground({}) == 0);
  CHECK(crown_ground({.over_level2 = 0.35f}) == 0);
  // Where the level-2 surface lies on the crown (hills_s2104), the next ring meeting the
  // crown's own face over it, and nothing farther, says the same.
  CHECK(crown_ground({.over_level2 = 0.1f, .above = Crown::kFace}) == 0);
  // On the level-2 surface with the next ring meeting the sky or ground farther on: a real
  // ring's drop-outs on dark ground break the ground's line alike.
  CHECK(crown_ground({.over_level2 = 0.1f}) == 9);
  CHECK(crown_ground({.over_level2 = 0.1f, .above = Crown::kFarther}) == 9);
  // Level with the line, as a floor the sensor stands on meets the next ring: no face.
  CHECK(crown_ground({.over_level2 = 0.1f, .above = Crown::kLevel}) == 9);
  CHECK(crown_ground({.above = Crown::kFarther}) == 0);
  // Cut only by steps in range, no column dropped (as ground behind bushes on a bank's
  // top): the nearest part stands out alone (the sky past it), the others stay.
  CHECK(crown_ground({.step_in_m = 1.2f, .dropped = 0}) == 6);
  // Closed at one outer end (the ring goes on nearer past it): no silhouette.
  CHECK(crown_ground({.nearer_after = true}) == 9);
  // On the level-2 surface, the sky past both ends and then the ring farther on both sides
  // (or far under the line): under the sensor a falling ray meets nothing only past terrain
  // falling out of its reach, so the line stands alone (hills_s6505: ring 2 on an object 16 m
  // out on a hillside steepening downwards, past the sky 17.5 m and 47 m out).
  CHECK(crown_ground({.over_level2 = 0.1f, .past_r = 45.f, .past_z = -0.3f}) == 0);
  CHECK(crown_ground({.over_level2 = 0.1f, .past_r = 27.1f, .past_z = -0.5f}) == 0);
  // The ring back at the line's range and height past a drop-out (dark ground) ...
  CHECK(crown_ground({.over_level2 = 0.1f, .past_r = 27.1f, .past_z = 0.1f}) == 9);
  // ... farther on one side only (the data ending on the other) ...
  CHECK(crown_ground({.over_level2 = 0.1f, .past_r = 45.f, .past_z = -0.3f, .past_both = false}) ==
        9);
  // ... or farther with no sky between: the line's ends open onto the terrain going on.
  CHECK(crown_ground({.over_level2 = 0.1f, .past_r = 45.f, .past_z = -0.3f, .past_sky = 0}) == 9);
}

TEST_CASE("column profiles: a ring's object past a hidden top is one object",
          "[detector][profiles]") {
  // Sim bank_s6701: rings 1-10 climb a bank's face at 0.35 to 17 m out, where its top
  // levels off out of the rings' sight; ring 11 meets an object 31.7 m out, 1.9 m over the
  // ring-10 ground, and ring 12 its crown over some of its columns. Where ring 11's return
  // is its column's last the walk refuses it (past a hidden top); where ring 12 is over it
  // (refused: 1.6 m over it, 2.4 m farther), it took it. Nearer bushes 16 m out bound the line (no
  // silhouette).
  struct Line {
    int first = 10, last = 17;  // ring 11's columns on the object
    int covered_to = 14;        // ring 12 over ring 11 up to this column
    float crown_z = 7.f;        // ring 12's height
    float crown_r = 34.1f;      // ... and range
    float recede_m = 0.f;       // ring 11's line receding by this per column
    float ring13_r = 0.f;       // ring 13 over the covered columns (0: none)
    float ring13_z = 0.f;
  };
  const auto ring11_ground = [](Line line) {
    Scan s;
    for (int ring = 0; ring <= 13; ++ring) {
      for (int col = 0; col < 30; ++col) {
        if (ring <= 10) {
          const float r = ring == 0 ? 6.f : 7.f + static_cast<float>(ring);
          add(s, ring, col, r, 0.35f * std::max(0.f, r - 7.f), 1);
        } else if (ring == 11 && (col == line.first - 1 || col == line.last + 1)) {
          add(s, ring, col, 16.f, 3.9f, 2);  // a bush
        } else if (ring == 11 && col >= line.first && col <= line.last) {
          add(s, ring, col, 31.7f + line.recede_m * static_cast<float>(col - line.first), 5.4f, 2);
        } else if (ring == 12 && col >= line.first && col <= line.covered_to) {
          const float recede = line.recede_m * static_cast<float>(col - line.first);
          add(s, ring, col, line.crown_r + recede, line.crown_z, 2);
        } else if (ring == 13 && line.ring13_r > 0.f && col >= line.first &&
                   col <= line.covered_to) {
          add(s, ring, col, line.ring13_r, line.ring13_z, 1);
        }
      }
    }
    const auto ground = label(s).ground;
    return ground_on_ring(s, ground, 11);
  };
  CHECK(ring11_ground({}) == 0);
  // Covered over all its columns, no bare return: the walk's labels stand.
  CHECK(ring11_ground({.covered_to = 17}) == 8);
  // Ring 12 over it rising on at 0.25, taken: the climb's surface rising on, ground.
  CHECK(ring11_ground({.crown_z = 6.f}) == 5);
  // Ring 12 over it 6 m farther, refused as well: rising on at 0.3 from it, a hillside rising
  // on past a hidden dip (hills_s903 dual: ring 11 35.8 m out over ring 10's hillside 30 m
  // out): ground; rising at 0.77, steeper than any ground, the object's crown: dropped.
  CHECK(ring11_ground({.crown_z = 7.2f, .crown_r = 37.7f}) == 5);
  // Ring 13 over the covered columns on a hillside 60 m out, taken: the terrain rising on
  // shows in the rings over the covered returns, which stay ground.
  CHECK(ring11_ground({.ring13_r = 60.f, .ring13_z = 9.f}) == 5);
  // A shorter line (5 columns) drops its covered returns too, but not where it recedes
  // along the rays more than it runs across them (0.75 m a column, 3 m over 2.2 m across: a
  // hillside receding along the ring, hills_s5904 tilted).
  CHECK(ring11_ground({.last = 14, .covered_to = 12}) == 0);
  CHECK(ring11_ground({.last = 14, .covered_to = 12, .recede_m = 0.75f}) == 3);
  CHECK(ring11_ground({.crown_z = 10.f, .crown_r = 37.7f}) == 0);
  // A long line (29 columns, 16 m): a hillside rising on far past a hidden dip, with objects
  // over some of it: the covered returns stay ground.
  CHECK(ring11_ground({.first = 1, .last = 28, .covered_to = 20}) == 20);
}

TEST_CASE("column profiles: the ground between two objects' feet is not an object",
          "[detector][profiles]") {
  // Sim fences_s6904 at 20 Hz: two low fences 5-8 m out recede past rings 0 and 1's ground
  // ranges and come back; each ring runs continuously down each fence's face onto the
  // ground between them, so each whole line (3.3-4.5 m) stands out, the other ring's line
  // as well, with the ring's ground going on past both ends.
  struct Scene {
    float middle_z = 0.f;      // ring 0's ground between the fences
    float outer_r = 6.85f;     // ... and outside them
    float after_r = 6.85f;     // ... past the second fence
    bool past_face = false;    // ring 0's return before the first fence on a post's foot
    bool ground_after = true;  // ring 0 meets the ground past the second fence
    int missing_fence = 0;     // ring 0 meets ground and drops out over 3 columns there (1, 2)
    bool piece_after = false;  // ring 0 meets only 3 columns of ground past the second fence
  };
  const auto middle_ground = [](Scene scene) {
    Scan s;
    const auto fence = [](int col) {  // 0 at a fence's foot, 1 at its nearest column
      if (col >= 20 && col < 30) return static_cast<float>(29 - col) / 9.f;
      if (col >= 50 && col < 60) return static_cast<float>(col - 50) / 9.f;
      return -1.f;
    };
    const float ground_r[] = {6.85f, 8.f};
    for (int ring = 0; ring < 2; ++ring) {
      const float r = ground_r[ring];
      for (int col = 0; col < 100; ++col) {
        const int fence_no = col < 40 ? 1 : 2;
        const bool missing = ring == 0 && scene.missing_fence == fence_no;
        const float f = missing ? -1.f : fence(col);
        if (missing && (fence_no == 1 ? col >= 27 && col < 30 : col >= 50 && col < 53)) continue;
        if (scene.piece_after && ring == 0 && col >= 60 && (col < 63 || col > 65)) continue;
        const float z = ring == 0 && col >= 30 && col < 50 ? scene.middle_z : 0.f;
        if (scene.past_face && col == 19 && ring < 2) {
          // The post's foot 0.12 m under the ground on both sides, ring 1 on it over it:
          // steep and off the profile's band, refused.
          add(s, ring, col, 6.85f, ring == 0 ? -0.12f : 0.2f, 2);
        } else if (f >= 0.f) {
          add(s, ring, col, r - (r - 4.9f) * f,
              0.01f + (0.53f + 0.3f * static_cast<float>(ring)) * f, 2);
        } else if (ring > 0 || (col >= 30 && col < 50)) {
          add(s, ring, col, r, z, 1);
        } else if (col < 50 || scene.ground_after) {
          add(s, ring, col, col < 50 ? scene.outer_r : scene.after_r, 0.f, 1);
        }
      }
    }
    const auto ground = label(s).ground;
    return ground_on_ring(s, ground, 0, 50) - ground_on_ring(s, ground, 0, 30);
  };
  CHECK(middle_ground({}) == 20);
  // The sky past one end: nothing says the ring goes on past the line.
  CHECK(middle_ground({.ground_after = false}) == 0);
  // Ground level with the ring's ground past the ends (within the walk's 0.15 m) and at its
  // range (the run gap), or not.
  CHECK(middle_ground({.middle_z = 0.1f}) == 20);
  CHECK(middle_ground({.middle_z = 0.16f}) == 0);
  CHECK(middle_ground({.middle_z = -0.2f}) == 0);
  CHECK(middle_ground({.outer_r = 7.5f}) == 0);
  CHECK(middle_ground({.outer_r = 7.1f}) == 0);
  CHECK(middle_ground({.missing_fence = 1}) == 0);
  CHECK(middle_ground({.missing_fence = 2}) == 0);
  CHECK(middle_ground({.piece_after = true}) == 0);
  CHECK(middle_ground({.after_r = 7.1f}) == 0);
  CHECK(middle_ground({.past_face = true}) == 0);
}
