// Level 3's driver (docs/detector.md, "Column profiles"): the returns gathered by column,
// each column walked (column_walk.cpp), then the checks along the rings (ring_runs.cpp,
// ring_lines.cpp) and down the columns (column_rises.cpp), and the labels written back.
#include "column_profile.hpp"

#include <algorithm>
#include <array>

namespace vlpground::detail {

using Index = std::size_t;

void ColumnProfiles::label(const Cloud& cloud, const std::uint8_t* steep,
                           const Level2Coverage& level2,
                           const std::vector<float>& plane_height, const ProfileParams& params,
                           std::vector<std::uint8_t>& ground, std::vector<float>& height) {
  p_ = params;
  steep_ = steep;
  level2_ = level2;
  start_z_ = p_.sensor_z > 0.f ? 0.f : p_.vehicle.at(p_.sensor_x, p_.sensor_y);
  const Index strongest = strongest_end(cloud);
  // height: over level 2 until the walk puts each return's height over its profile there
  gather_by_column(cloud, steep, height, strongest);
  const Index columns = column_start_.size() - 1;
  // In a local: the passes below live in other files and might, for all the compiler knows,
  // resize column_start_ (they do not), so its data would be reloaded at every column.
  const std::uint32_t* const column_start = column_start_.data();
  ring_reach_.resize(columns * kLasers);
  if (columns > 0) note_ring_reach(0);
  hidden_tops_.clear();
  for (Index c = 0; c < columns; ++c) {
    if (c + 1 < columns) note_ring_reach(c + 1);  // ray_reaches looks one column ahead
    walk_column(c, column_start[c], column_start[c + 1], plane_height, height);
  }
  find_ring_runs(cloud, strongest);  // for the silhouettes and the shadows
  drop_covered_tops(cloud);
  drop_short_level_runs(cloud);
  // Silhouettes first: an object standing out (a facade's ring line that the walk took past
  // a fence line) must not vouch for a single rise below it.
  remove_silhouettes(cloud);
  drop_wall_lines(cloud);
  drop_refuted_rises(cloud);
  ground.resize(cloud.size());
  shadowed_.resize(cloud.size());
  for (Index c = 0; c < columns; ++c) {
    const bool dropped_group = drop_raised_groups(column_start[c], column_start[c + 1]);
    check_single_rises(cloud, column_start[c], column_start[c + 1]);
    if (dropped_group) drop_orphaned_feet(column_start[c], column_start[c + 1]);
  }
  // The labels, by cloud point; arrays in locals (a byte store may alias any member).
  const ColumnPoint* const points = points_.data();
  std::uint8_t *const labels = ground.data(), *const shadowed = shadowed_.data();
  for (Index k = 0; k < points_.size(); ++k) {
    labels[points[k].index] = points[k].ground;
    shadowed[points[k].index] = points[k].shadowed;
  }
  for (const RingRun& run : runs_) fill_shadows(cloud, run, ground);
  keep_past(strongest);
}

// This frame's points by column become the previous frame's (swapped, not copied: the next
// frame's gather overwrites the buffers it gets back). The buffers handed back grow with
// the ones kept, so that each frame finds room as with one buffer (no allocation once the
// largest frame has been seen).
void ColumnProfiles::keep_past(Index strongest_end) {
  past_points_.swap(points_);
  past_column_start_.swap(column_start_);
  points_.reserve(past_points_.size());
  column_start_.reserve(past_column_start_.size());
  past_strongest_end_ = strongest_end;
}

// The cloud's points by column into points_ (what the walk reads, gathered so that it reads
// sequentially). The cloud is in (layer, ring, column) order: its rows, one per layer and
// ring, each hold at most one point per column, column-ascending. Each column takes the
// next point of every row that has one there, rows in cloud order, so that its points come
// out ring-ascending per layer (already in walking order when the cloud has one layer).
// Read row by row, written in order: a scatter by column was a cache miss per point.
void ColumnProfiles::gather_by_column(const Cloud& cloud, const std::uint8_t* steep,
                                      const std::vector<float>& level2_height, Index strongest) {
  const RingRuns layers[2] = {point_ring_runs(cloud, 0, strongest),
                              point_ring_runs(cloud, strongest, cloud.size())};
  std::array<std::uint32_t, 2 * kLasers> next{}, row_end{};
  Index rows = 0;
  int columns = 0;
  for (const RingRuns& runs : layers) {
    for (int ring = 0; ring < kLasers; ++ring) {
      const Index begin = runs[static_cast<Index>(ring)], end = runs[static_cast<Index>(ring) + 1];
      if (begin == end) continue;
      next[rows] = static_cast<std::uint32_t>(begin);
      row_end[rows++] = static_cast<std::uint32_t>(end);
      columns = std::max(columns, cloud.column[end - 1] + 1);
    }
  }
  column_start_.resize(static_cast<Index>(columns) + 1);
  points_.resize(cloud.size());
  position_.resize(cloud.size());
  // Plain pointers in locals: a store through one may alias the vectors' own pointers.
  const std::uint16_t *const column = cloud.column.data(), *const ring = cloud.ring.data();
  const float *const range = cloud.range_xy.data(), *const z = cloud.z.data();
  const float* const level2 = level2_height.data();
  std::uint32_t* const start = column_start_.data();
  std::uint32_t* const position = position_.data();
  ColumnPoint* const out = points_.data();
  std::uint32_t k = 0;
  for (int c = 0; c < columns; ++c) {
    start[c] = k;
    for (Index row = 0; row < rows; ++row) {
      for (std::uint32_t i = next[row]; i != row_end[row] && column[i] == c; i = ++next[row]) {
        position[i] = k;
        ColumnPoint& q = out[k++];
        q = {range[i], z[i], level2[i], i, static_cast<std::uint8_t>(ring[i]), steep[i], 0};
      }
    }
  }
  start[columns] = k;
  if (strongest != cloud.size()) merge_layers();
}

// Each column's returns of both layers merged by ring and range with an insertion sort
// (at most 32 points per column); position_ follows.
void ColumnProfiles::merge_layers() {
  auto before = [](const ColumnPoint& u, const ColumnPoint& w) {
    return u.ring != w.ring ? u.ring < w.ring : u.r < w.r;
  };
  for (Index c = 0; c + 1 < column_start_.size(); ++c) {
    ColumnPoint* first = points_.data() + column_start_[c];
    ColumnPoint* last = points_.data() + column_start_[c + 1];
    for (ColumnPoint* a = first + 1; a < last; ++a) {
      if (!before(*a, *(a - 1))) continue;
      const ColumnPoint v = *a;
      ColumnPoint* b = a;
      for (; b > first && before(v, *(b - 1)); --b) *b = *(b - 1);
      *b = v;
    }
  }
  for (Index k = 0; k < points_.size(); ++k) position_[points_[k].index] = static_cast<std::uint32_t>(k);
}

// Column c's farthest return per ring (0: none), for ray_reaches; a column is sorted by ring
// and range, so the last return of a ring is its farthest.
void ColumnProfiles::note_ring_reach(Index c) {
  float* reach = ring_reach_.data() + c * kLasers;
  std::fill(reach, reach + kLasers, 0.f);
  for (Index k = column_start_[c]; k < column_start_[c + 1]; ++k) reach[points_[k].ring] = points_[k].r;
}

}  // namespace vlpground::detail
