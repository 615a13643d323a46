// Level 3's driver (docs/detector.md, "Column profiles"): the returns gathered by column,
// each column walked (column_walk.cpp), then the checks along the rings (ring_runs.cpp,
// ring_lines.cpp) and down the columns (column_rises.cpp), and the labels written back.
#include "column_profile.hpp"

#include <algorithm>

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
  gather_by_column(cloud, steep, height, strongest == cloud.size());
  const Index columns = column_start_.size() - 1;
  // In a local: the passes below live in other files and might, for all the compiler knows,
  // resize column_start_ (they do not), so its data would be reloaded at every column.
  const std::uint32_t* const column_start = column_start_.data();
  ring_reach_.resize(columns * kLasers);
  if (columns > 0) note_ring_reach(0);
  for (Index c = 0; c < columns; ++c) {
    if (c + 1 < columns) note_ring_reach(c + 1);  // ray_reaches looks one column ahead
    walk_column(c, column_start[c], column_start[c + 1], plane_height, height);
  }
  find_ring_runs(cloud, strongest);  // for the silhouettes and the shadows
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
  for (const RingRun& run : runs_) fill_shadows(cloud, run.a, run.b + 1, ground);
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

// Counting sort by column into points_ (what the walk reads, gathered so that it reads
// sequentially); the cloud is in (layer, ring, column) order, so each column's points come
// out ring-ascending per layer, already in walking order when the cloud has one layer.
void ColumnProfiles::gather_by_column(const Cloud& cloud, const std::uint8_t* steep,
                                      const std::vector<float>& level2_height,
                                      bool one_layer) {
  int columns = 0;
  for (Index i = 0; i < cloud.size(); ++i) columns = std::max(columns, cloud.column[i] + 1);
  column_start_.assign(static_cast<Index>(columns) + 1, 0);
  for (Index i = 0; i < cloud.size(); ++i) ++column_start_[cloud.column[i] + 1u];
  for (Index c = 1; c < column_start_.size(); ++c) column_start_[c] += column_start_[c - 1];
  cursor_.assign(column_start_.begin(), column_start_.end() - 1);
  points_.resize(cloud.size());
  position_.resize(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) {
    position_[i] = cursor_[cloud.column[i]]++;
    ColumnPoint& q = points_[position_[i]];
    q = {cloud.range_xy[i], cloud.z[i], level2_height[i], static_cast<std::uint32_t>(i),
         static_cast<std::uint8_t>(cloud.ring[i]), steep[i], 0};
  }
  if (!one_layer) merge_layers();
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
