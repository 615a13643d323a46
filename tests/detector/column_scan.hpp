// A synthetic scan for the column-profile tests (level 3 of the terrain model): 360 columns
// and 12 rings over a road with a bank rising on one side, fields 2 m under a levee on
// another, a wall, and a crate seen by the top ring against the sky (a silhouette); and
// small scans of single columns, labelled through ColumnProfiles::label.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "column_profile.hpp"
#include "steep.hpp"

namespace column_scan {

using namespace vlpground::detail;

inline constexpr int kColumns = 360, kRings = 12;
inline constexpr float kDeg = 3.14159265f / 180.f;

inline float ring_range(int ring) { return 6.f + 1.5f * static_cast<float>(ring); }

// The terrain: level road; fields 2 m lower beyond x = 12, the levee's side (x 10..12) in
// its shadow (a drop steeper than any ground gradient); a bank rising at 0.3 beyond
// y = -5; seen from (0, 0), mounting height known.
inline bool in_shadow(float x) { return x > 10.f && x < 12.f; }
inline float terrain(float x, float y) {
  if (x >= 12.f) return -2.f;
  if (y < -5.f) return 0.3f * (-5.f - y);
  return 0.f;
}

inline bool wall_column(int col) { return col >= 80 && col <= 100; }  // a wall 12 m out at +y
inline bool box_cell(int ring, int col) { return ring == 11 && col >= 200 && col <= 205; }

struct Scan {
  Cloud cloud;
  std::vector<int> truth;  // 1 ground, 2 obstacle
};

inline void add(Scan& s, int ring, int col, float r, float z, int truth) {
  const float a = static_cast<float>(col) * kDeg;
  Cloud& c = s.cloud;
  c.x.push_back(r * std::cos(a));
  c.y.push_back(r * std::sin(a));
  c.z.push_back(z);
  c.range_xy.push_back(r);
  c.cell.push_back(static_cast<std::uint32_t>(ring * kColumns + col));
  c.layer.push_back(0);
  c.ring.push_back(static_cast<std::uint16_t>(ring));
  c.column.push_back(static_cast<std::uint16_t>(col));
  s.truth.push_back(truth);
}

// One column (column 0) of ground returns, ring k at range r[k] and height z[k].
inline Scan ground_column(const std::vector<float>& r, const std::vector<float>& z) {
  Scan s;
  for (std::size_t ring = 0; ring < z.size(); ++ring) {
    add(s, static_cast<int>(ring), 0, r[ring], z[ring], 1);
  }
  return s;
}

inline Scan make_scan() {
  Scan s;
  for (int ring = 0; ring < kRings; ++ring) {  // cloud order: layer, ring, column
    for (int col = 0; col < kColumns; ++col) {
      const float r = ring_range(ring), a = static_cast<float>(col) * kDeg;
      if (wall_column(col) && r >= 12.f) {
        add(s, ring, col, 12.f, 0.3f * static_cast<float>(ring - 3), 2);
      } else if (box_cell(ring, col)) {
        add(s, ring, col, 22.5f, 0.35f, 2);  // a crate the column alone would take
      } else if (ring < kRings - 1 && !in_shadow(r * std::cos(a))) {  // the top ring: sky
        add(s, ring, col, r, terrain(r * std::cos(a), r * std::sin(a)), 1);
      }
    }
  }
  return s;
}

struct Labels {
  std::vector<std::uint8_t> ground;
  std::vector<float> height;
};

// Labels a scan with the mounting height known, the level-2 surface having ground of its own
// under return i where measured[i]; `level2` and `plane` default to a level-2 surface at
// z = 0 and no trusted level-1 plane.
// With `kept`, that instance labels the scan (it keeps the frame before); the scan is then a
// fragment of a rotation going on from that frame when `continues_previous`.
// `base` gives the other parameters (defaults: the detector's).
inline Labels label_by_cell(const Scan& s, std::vector<float> level2, std::vector<float> plane,
                            const std::vector<bool>& measured, ColumnProfiles* kept = nullptr,
                            bool continues_previous = false, const ProfileParams& base = {}) {
  if (level2.empty()) level2.assign(s.cloud.size(), 0.f);
  if (plane.empty()) plane.assign(s.cloud.size(), std::nanf(""));
  std::vector<std::uint8_t> steep;
  mark_steep(s.cloud, steep);
  FaceTable faces;
  add_faces_across_gaps(s.cloud, faces, steep);  // as the detector gives the profiles
  ProfileParams p = base;
  p.sensor_z = 1.8f;  // mounting height known: the ground under the sensor is z = 0
  p.continues_previous = continues_previous;
  ColumnProfiles own;
  ColumnProfiles& profiles = kept != nullptr ? *kept : own;
  Labels out;
  out.height = level2;  // heights over the level-2 surface on entry
  // A measured return in fitting bin 0, whose cell 0 is measured; the others in no bin.
  std::vector<std::int32_t> point_bin(s.cloud.size());
  for (std::size_t i = 0; i < point_bin.size(); ++i) point_bin[i] = measured[i] ? 0 : -1;
  const std::int32_t cell_of_bin[] = {0};
  const CellState cell_state[] = {CellState::refined};
  const Level2Coverage coverage{point_bin.data(), cell_of_bin, cell_state};
  profiles.label(s.cloud, steep.data(), coverage, plane, p, out.ground, out.height);
  return out;
}

// As label_by_cell, with the level-2 surface having ground of its own under every return
// when `measured`, under none otherwise.
inline Labels label(const Scan& s, std::vector<float> level2 = {}, std::vector<float> plane = {},
                    bool measured = false) {
  return label_by_cell(s, std::move(level2), std::move(plane),
                       std::vector<bool>(s.cloud.size(), measured));
}

// One column of returns (ring, range, z, height over the level-2 surface, which has ground
// of its own), with their heights over a level-1 plane (empty: none), labelled.
struct ColumnReturn {
  int ring;
  float r, z, h;
};
inline std::vector<int> label_column(const std::vector<ColumnReturn>& column,
                                     std::vector<float> plane = {}) {
  Scan s;
  std::vector<float> level2;
  for (const ColumnReturn& q : column) {
    add(s, q.ring, 0, q.r, q.z, 1);
    level2.push_back(q.h);
  }
  const Labels out = label(s, std::move(level2), std::move(plane), true);
  return {out.ground.begin(), out.ground.end()};
}

// Labels of a column where the level-1 plane lies where the level-2 surface does (every
// return's height over the plane is its h).
inline std::vector<int> label_column_on_plane(const std::vector<ColumnReturn>& column) {
  std::vector<float> plane;
  for (const ColumnReturn& q : column) plane.push_back(q.h);
  return label_column(column, std::move(plane));
}

// Ground at 6 m, a car side at 8 m (rings 1-3), then ring 4 at (r, z).
inline Scan car_then(float r, float z, int truth) {
  Scan s;
  add(s, 0, 0, 6.f, 0.f, 1);
  for (int ring = 1; ring <= 3; ++ring) add(s, ring, 0, 8.f, 0.3f * static_cast<float>(ring), 2);
  add(s, 4, 0, r, z, truth);
  return s;
}

// Sim fences_s101: ring 0 on the road 7.4 m out, rings 1-4 on a 1 m wall 8.1 m out;
// rings 5 and 6 pass over it to the tops of fences 18 and 25 m out (z5, z6 over the road).
inline Scan wall_then_fence_tops(float z5, float z6) {
  Scan s;
  add(s, 0, 0, 7.4f, 0.f, 1);
  for (int ring = 1; ring <= 4; ++ring) {
    add(s, ring, 0, 8.1f, 0.1f + 0.29f * static_cast<float>(ring - 1), 2);
  }
  add(s, 5, 0, 17.9f, z5, 2);
  add(s, 6, 0, 25.f, z6, 2);
  return s;
}

// One column (0) up a bank face rising at 0.3 from 6 m: rings 0-4 out to (10 m, 1.2 m).
inline Scan bank_face() {
  Scan s;
  for (int ring = 0; ring <= 4; ++ring) {
    add(s, ring, 0, 6.f + static_cast<float>(ring), 0.3f * static_cast<float>(ring), 1);
  }
  return s;
}

// Rings 0 .. rings - 1 up a bank face rising at 0.35 from 10 m, a metre apart, over columns
// 0 .. columns - 1 (sim bank: the face the top rings leave for the bank's top).
inline void add_bank_rings(Scan& s, int rings, int columns) {
  for (int ring = 0; ring < rings; ++ring) {
    const float r = 10.f + static_cast<float>(ring);
    for (int col = 0; col < columns; ++col) add(s, ring, col, r, 0.35f * (r - 10.f), 1);
  }
}

// How many returns of ring `ring` in columns before `column_end` are labelled ground.
inline int ground_on_ring(const Scan& s, const std::vector<std::uint8_t>& ground, int ring,
                          int column_end = kColumns) {
  int taken = 0;
  for (std::size_t i = 0; i < ground.size(); ++i) {
    if (s.cloud.ring[i] == ring && s.cloud.column[i] < column_end) taken += ground[i];
  }
  return taken;
}

// A bowl z = 0.004 r^2 seen by five rings (6, 8, 11, 15, 20 m) over 60 columns 1 degree
// apart; in columns 20-39 a box 5 m out hides rings 0-3 and ring 4 sees the bowl past it
// at `shadow_z` (1.6 m: the bowl; higher: something standing on it).
inline Scan bowl_behind_box(float shadow_z) {
  const float range[] = {6.f, 8.f, 11.f, 15.f, 20.f};
  Scan s;
  for (int ring = 0; ring < 5; ++ring) {
    for (int col = 0; col < 60; ++col) {
      const bool hidden = col >= 20 && col < 40;
      const float r = range[ring];
      if (hidden && ring < 4)
        add(s, ring, col, 5.f, 0.3f * static_cast<float>(ring + 1), 2);
      else
        add(s, ring, col, r, hidden ? shadow_z : 0.004f * r * r, hidden && shadow_z > 1.7f ? 2 : 1);
    }
  }
  return s;
}

// A hill behind a box and a post (sim hills_s4, frame 2, ring 7 past a box 8.7 m out): the
// box, 5 m out, hides rings 0-3 in columns 18-39, and ring 4, 20 m out, runs on past it on
// the hill, 1.6 m up. In the columns before `open` open ones a post as tall as ring 4
// stands (or, without `post`, ring 4 drops out there), so that ring 4 sees the hill before
// the shadow only in the open columns. With `wall`, ring 4 meets a wall's foot past the box
// instead, rings 5-7 the wall over it.
inline Scan hill_behind_box_and_post(int open, bool post, bool wall) {
  const float range[] = {6.f, 8.f, 11.f, 15.f, 20.f};
  const int post_end = 18 - open, post_begin = post_end - 6;
  Scan s;
  for (int ring = 0; ring < (wall ? 8 : 5); ++ring) {
    for (int col = 0; col < 60; ++col) {
      const bool box = col >= 18 && col < 40, beside = col >= post_begin && col < post_end;
      if (ring > 4) {
        if (box) add(s, ring, col, 20.f, 1.63f + 0.4f * static_cast<float>(ring - 4), 2);
      } else if (beside && !post && ring == 4) {
        continue;  // ring 4 dropped out
      } else if (beside || (box && ring < 4)) {
        add(s, ring, col, 5.f, 0.3f * static_cast<float>(ring + 1), 2);
      } else {
        const float r = range[ring];
        add(s, ring, col, r, box ? (wall ? 1.63f : 1.6f) : 0.004f * r * r, 1);
      }
    }
  }
  return s;
}

}  // namespace column_scan
