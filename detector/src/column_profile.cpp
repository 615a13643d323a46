#include "column_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

namespace vlpground::detail {

namespace {
using Index = std::size_t;

// high_on_face: a hit this far over a lower ring's hit on the same face, itself an obstacle.
constexpr float kFaceTwoRings_m = 0.4f;

// Whether returns a and b lie at least `distance` apart horizontally.
bool apart(const Cloud& cloud, Index a, Index b, float distance) {
  const float dx = cloud.x[b] - cloud.x[a], dy = cloud.y[b] - cloud.y[a];
  return dx * dx + dy * dy >= distance * distance;
}

// Whether returns a and b lie within `limit` of each other in horizontal range and height
// (the run gap's test; mark_continuous does the same inline, vectorised).
bool close_in_range_and_height(const Cloud& cloud, Index a, Index b, float limit) {
  const float dr = cloud.range_xy[b] - cloud.range_xy[a], dz = cloud.z[b] - cloud.z[a];
  return dr * dr + dz * dz <= limit * limit;
}
}  // namespace

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
  ring_reach_.resize(columns * kLasers);
  if (columns > 0) note_ring_reach(0);
  for (Index c = 0; c < columns; ++c) {
    if (c + 1 < columns) note_ring_reach(c + 1);  // ray_reaches looks one column ahead
    walk_column(c, column_start_[c], column_start_[c + 1], plane_height, height);
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
    const bool dropped_group = drop_raised_groups(column_start_[c], column_start_[c + 1]);
    check_single_rises(cloud, column_start_[c], column_start_[c + 1]);
    if (dropped_group) drop_orphaned_feet(column_start_[c], column_start_[c + 1]);
  }
  // The labels, by cloud point; arrays in locals (a byte store may alias any member).
  const ColumnPoint* const points = points_.data();
  std::uint8_t *const labels = ground.data(), *const shadowed = shadowed_.data();
  for (Index k = 0; k < points_.size(); ++k) {
    labels[points[k].index] = points[k].ground;
    shadowed[points[k].index] = points[k].shadowed;
  }
  for (const RingRun& run : runs_) fill_shadows(cloud, run.a, run.b + 1, ground);
}

// Along each ring (strongest layer), runs of returns continuous in space: the run [a, b]
// of the ring's returns [first, last), found once per frame (positions only).
void ColumnProfiles::find_ring_runs(const Cloud& cloud, Index strongest_end) {
  runs_.clear();
  mark_continuous(cloud, strongest_end);
  const RingRuns rows = point_ring_runs(cloud, 0, strongest_end);
  for (int ring = 0; ring < kLasers; ++ring) {
    const Index first = rows[static_cast<Index>(ring)], last = rows[static_cast<Index>(ring) + 1];
    const Index first_run = runs_.size();
    Index a = first;
    while (a < last) {
      Index b = a;
      while (b + 1 < last && (continuous_[b] != 0 || bridged_over_sensor(cloud, b))) ++b;
      runs_.push_back({first, last, a, b});
      a = b + 1;
    }
    const Index last_run = runs_.size() - 1;
    if (first < last && last_run > first_run && continuous_across_edge(cloud, last - 1, first)) {
      runs_[first_run].wrap = last_run;
      runs_[last_run].wrap = first_run;
    }
  }
}

// Whether the ring's last return (`end`, at the frame's last columns) and its first
// (`start`, at the first columns) are continuous across the frame's edge: within
// run_column_gap columns of each other around the rotation, and close in range, height and
// position (a frame that is not a whole rotation leaves them far apart), by kEdgeMotionSlack
// times the run gap: the vehicle moved between the two ends of the rotation (0.6-0.7 m on a
// ramp at 5 Hz, garage_s5; hills_s3).
bool ColumnProfiles::continuous_across_edge(const Cloud& cloud, Index end, Index start) const {
  const int columns = static_cast<int>(column_start_.size()) - 1;
  const int gap = static_cast<int>(cloud.column[start]) + columns - static_cast<int>(cloud.column[end]);
  const float limit = kEdgeMotionSlack * run_gap(cloud.range_xy[end]);
  return gap <= p_.run_column_gap && close_in_range_and_height(cloud, end, start, limit) &&
         !apart(cloud, end, start, limit);
}

// Level ground taken running on past a face under the sensor (ColumnPoint::level_run) lies
// on a ring run longer than level_run_min_m (the chord between its ends; a run across the
// frame's edge counts as long): the street beside a ramp runs on along the ring between the
// cars parked on it, where roofs past a car's side are short runs between nearer returns
// (jam). Dropped, such a return is refused past an obstacle in front, as the walk would
// have refused it: fill_shadows may still take it from the ring.
void ColumnProfiles::drop_short_level_runs(const Cloud& cloud) {
  for (const RingRun& run : runs_) {
    if (run.wrap != kNoRun || apart(cloud, run.a, run.b, p_.level_run_min_m)) continue;
    for (Index i = run.a; i <= run.b; ++i) {
      ColumnPoint& q = points_[position_[i]];
      if (q.level_run == 0) continue;
      q.ground = 0;
      q.shadowed = kShadow;
    }
  }
}

// Terrain seen by a ring is a long continuous curve: a short run whose both ends border the
// sky (no return) or returns behind it (farther away) is an object standing out: a tree
// crown, a shed or a fence over ground the rings do not see, or in front of ground seen
// farther on. (Ground refused in the shadow of an obstacle within a run is filled in
// afterwards: fill_shadows.)
void ColumnProfiles::remove_silhouettes(const Cloud& cloud) {
  stands_out_.assign(cloud.size(), 0);
  for (const RingRun& run : runs_) {
    // A run going on across the frame's edge is judged whole, from its part before the edge
    // (the ring's last run) to its part after it (the ring's first run).
    if (run.wrap != kNoRun && run.a != run.first) continue;
    const RingRun* before = run.wrap != kNoRun ? &runs_[run.wrap] : nullptr;
    const Index outer_a = before != nullptr ? before->a : run.a;
    if (before != nullptr && !under_half_turn(cloud, before->a, run.b)) continue;
    if (!stands_out(cloud, run.first, run.last, outer_a, run.b)) continue;
    if (before != nullptr) mark_standing_out(*before);
    mark_standing_out(run);
  }
  mark_broken_silhouettes(cloud);
  for (const RingRun& run : runs_) {
    if (stands_out_[run.a] == 0 || (run.wrap != kNoRun && run.a != run.first)) continue;
    remove_silhouette(cloud, run, run.wrap != kNoRun ? &runs_[run.wrap] : nullptr);
  }
}

// An object that a small gap in its ring cut in two (a drop-out, its edge stepping back by
// more than the run gap; across the frame's edge too): neighbouring runs whose cut is small (within
// twice the run gap, fewer columns missing than the sky takes) stand out together when the
// whole is short (silhouette_max_m), the nearer part stands out and the other opens onto
// the sky at its far end and stands over the level-2 surface: a bush at a crest's far side,
// the ring seeing the sky on one side and the fields far below on the other (hills_s102).
// Only under the sensor: a run met by rising rays may end in the sky where the terrain does
// (a bank's top edge); a falling ray meets the sky only past terrain falling out of reach.
void ColumnProfiles::mark_broken_silhouettes(const Cloud& cloud) {
  const int columns = static_cast<int>(column_start_.size()) - 1;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    const std::size_t j = next_run(i);
    if (j == kNoRun || runs_[i].wrap != kNoRun || runs_[j].wrap != kNoRun) continue;
    const RingRun &one = runs_[i], &two = runs_[j];
    const bool out_one = stands_out_[one.a] != 0, out_two = stands_out_[two.a] != 0;
    if ((out_one && out_two) || cloud.z[one.b] >= p_.sensor_z || cloud.z[two.a] >= p_.sensor_z)
      continue;
    const int cut = (cloud.column[two.a] - cloud.column[one.b] + columns) % columns - 1;
    const float limit = 2.f * run_gap(cloud.range_xy[one.b]);
    if (cut >= p_.sky_columns || apart(cloud, one.b, two.a, limit) ||
        apart(cloud, one.a, two.b, p_.silhouette_max_m))
      continue;
    const bool two_nearer = cloud.range_xy[two.a] < cloud.range_xy[one.b];
    bool together = false;
    // The farther part must stand over the level-2 surface too (at both its ends): the
    // terrain seen elsewhere lies lower there. A real ring has drop-outs on dark ground that
    // look like the sky (vlp16_outdoor_600rpm: road 32 m out beside a car).
    auto raised = [&](const RingRun& part) {
      return raised_over_level2(position_[part.a], p_.single_rise_m) &&
             raised_over_level2(position_[part.b], p_.single_rise_m);
    };
    if (out_two && two_nearer) {
      together = outer_end_sky(cloud, one, false) && raised(one);
    } else if (out_one && !two_nearer) {
      together = outer_end_sky(cloud, two, true) && raised(two);
    }
    if (!together) continue;
    mark_standing_out(one);
    mark_standing_out(two);
  }
}

// A ring's line along a wall: a steep obstacle return high on its face (a lower ring of its
// column met the same face, within the run gap in range, more than drop_m lower) carries
// the object along its ring: the ground returns that follow it along the ring (in its run,
// either way) level with it (at most wall_line_band_m under it, or over it) are that object
// too, seen where no lower ring meets the face in their columns (a shed on a bank's top,
// whose face the bank hides from the rings below: bank_s101 at Hi-Res). The line ends at a
// steep return that is not high on its face (the ring came down to the face's foot), at a
// ground return under the band, and at an obstacle return that is not steep: where a ring
// runs along a ramp's retaining wall onto the street on its top, it crosses the wall's top
// edge first (garage_s2).
void ColumnProfiles::drop_wall_lines(const Cloud& cloud) {
  refuted_.clear();
  refuted_.reserve(points_.size());  // grown once, with the cloud
  for (const RingRun& run : runs_) {
    if (!ground_and_face(run)) continue;  // most runs are all ground or all obstacle
    follow_wall_lines(cloud, run, true);
    follow_wall_lines(cloud, run, false);
  }
  for (const std::uint32_t k : refuted_) points_[k].ground = 0;
}

// Whether run `run` holds both a ground return that is not steep and a steep obstacle
// return. Steep returns are few: a search of the frame's steep flags in cloud order, 8 at a
// time, rules most runs out first.
bool ColumnProfiles::ground_and_face(const RingRun& run) const {
  Index i = run.a;
  const Index end = run.b + 1;
  for (std::uint64_t word = 0; i + 8 <= end; i += 8) {
    std::memcpy(&word, steep_ + i, sizeof word);
    if (word != 0) break;
  }
  while (i < end && steep_[i] == 0) ++i;
  if (i == end) return false;
  bool ground = false, face = false;
  for (Index j = run.a; j < end && !(ground && face); ++j) {
    const ColumnPoint& q = points_[position_[j]];
    ground = ground || (q.ground != 0 && q.steep == 0);
    face = face || (q.ground == 0 && q.steep != 0);
  }
  return ground && face;
}

// One sweep of drop_wall_lines along run `run` (forward: in column order).
void ColumnProfiles::follow_wall_lines(const Cloud& cloud, const RingRun& run, bool forward) {
  // The last steep obstacle return of the line (kNone: no line); whether it is high on its
  // face is asked only when a ground return follows it (walls are long).
  Index face = kNone;
  int high = -1;  // -1: not asked yet
  for (Index n = 0; n <= run.b - run.a; ++n) {
    const Index k = position_[forward ? run.a + n : run.b - n];
    const ColumnPoint& q = points_[k];
    if (q.steep != 0) {  // the face goes on: high on it, or down to its foot
      face = q.ground == 0 ? k : kNone;
      high = -1;
      continue;
    }
    if (face != kNone && q.ground != 0 && q.z >= points_[face].z - p_.wall_line_band_m) {
      if (high < 0) high = high_on_face(cloud, face) ? 1 : 0;
      if (high != 0) {
        refuted_.push_back(static_cast<std::uint32_t>(k));
        continue;
      }
    }
    face = kNone;
  }
}

// Whether column point k (steep) lies more than drop_m over a lower ring's return of its
// column on the same face (within the run gap in range), or more than kFaceTwoRings_m over
// one that is itself an obstacle on a steep face: the face is then two rings tall, and
// rings 1.33 degrees apart (Puck Hi-Res) meet it only 0.45 m apart 20 m out (bank_s105).
bool ColumnProfiles::high_on_face(const Cloud& cloud, Index k) const {
  const ColumnPoint& q = points_[k];
  const Index begin = column_start_[cloud.column[q.index]];
  const float gap = run_gap(q.r);
  for (Index j = begin; j < k; ++j) {
    const ColumnPoint& low = points_[j];
    if (low.ring >= q.ring || std::abs(low.r - q.r) > gap) continue;
    const bool low_on_face = low.steep != 0 && low.ground == 0;
    if (q.z - low.z > (low_on_face ? kFaceTwoRings_m : p_.drop_m)) return true;
  }
  return false;
}

// Marks run `run`'s returns as standing out.
void ColumnProfiles::mark_standing_out(const RingRun& run) {
  std::fill(stands_out_.begin() + static_cast<std::ptrdiff_t>(run.a),
            stands_out_.begin() + static_cast<std::ptrdiff_t>(run.b) + 1, std::uint8_t{1});
}

// Whether run `run`'s last end (`after`) or first end opens onto the sky (sky_columns
// columns without a return).
bool ColumnProfiles::outer_end_sky(const Cloud& cloud, const RingRun& run, bool after) const {
  int gap = 0;
  static_cast<void>(beyond_end(cloud, run.first, run.last, after ? run.b : run.a, after, gap));
  return gap >= p_.sky_columns;
}

// The run after run i along its ring; across the frame's edge, the ring's first run for its
// last one; kNoRun for a ring of one run.
std::size_t ColumnProfiles::next_run(std::size_t i) const {
  const RingRun& run = runs_[i];
  if (run.b + 1 < run.last) return i + 1;
  std::size_t j = i;
  while (runs_[j].a != run.first) --j;  // the ring's first run
  return j == i ? kNoRun : j;
}

// Whether a run from return a (before the frame's edge) to b (after it) covers less than
// half the frame's columns: its extent, the chord between its ends, then measures it (a ring
// seen all around but for a gap has close ends too).
bool ColumnProfiles::under_half_turn(const Cloud& cloud, Index a, Index b) const {
  const int columns = static_cast<int>(column_start_.size()) - 1;
  const int span = static_cast<int>(cloud.column[b]) + columns - static_cast<int>(cloud.column[a]);
  return 2 * span < columns;
}

// The run standing out (with its part before the frame's edge, if any) is an object unless
// it carries the road the vehicle stands on (its column's first return level with the start,
// the next ground return of the column going on level behind it and not standing out) over
// shadow_anchor_m of the ring: that road seen over a short stretch (the vehicle near a
// levee's edge, a car beside it), not an object: the next ring passes over a tree crown level
// with the road to the fields, or meets the crown again, standing out as well; over a low
// object a higher ring sees the road only in its gaps.
void ColumnProfiles::remove_silhouette(const Cloud& cloud, const RingRun& run, const RingRun* before) {
  Index road_first = kNone, road_last = kNone;
  for (const RingRun* part : {before, &run}) {
    if (part == nullptr) continue;
    for (Index i = part->a; i <= part->b; ++i) {
      const std::uint32_t beyond = points_[position_[i]].road_beyond;
      if (beyond == kNoPoint || stands_out_[beyond] != 0) continue;
      if (road_first == kNone) road_first = i;
      road_last = i;
    }
  }
  if (road_first != kNone && apart(cloud, road_first, road_last, p_.shadow_anchor_m)) return;
  for (const RingRun* part : {before, &run}) {
    if (part == nullptr) continue;
    for (Index i = part->a; i <= part->b; ++i) points_[position_[i]].ground = 0;
  }
}

// Run [begin, end) of one ring: an obstacle near the sensor (a trunk, a box, a car) hides
// the lower rings of the columns behind it, and the walk refuses the ground a higher ring
// sees past it when that ground has risen more than the allowance past an obstacle (the
// far side of a bowl, a hill behind a tree). The ring itself runs on across the shadow: a
// stretch of such returns with ground on both sides is ground where it lies on the line
// joining that ground. The ground on each side must be seen over shadow_anchor_m, so that
// a lone ground return on a fence line anchors nothing. Single rises (rule 4) under the
// ground the vehicle stands on are taken the same way: a ring grazing a levee's side where
// the level-2 surface was fitted to the fields below.
void ColumnProfiles::fill_shadows(const Cloud& cloud, Index begin, Index end,
                                  std::vector<std::uint8_t>& ground) const {
  Index anchor = end;  // last return of a long enough ground stretch before a shadow
  Index start = end;   // first return of the ground stretch being walked
  bool long_stretch = false;
  for (Index i = begin; i < end; ++i) {
    if (ground[i] == 0) {
      start = end;
      long_stretch = false;
      if (shadowed_[i] == 0) anchor = end;  // an obstacle of the ring itself
      continue;
    }
    if (start == end) start = i;
    // The first ground return past a shadow: the ground beyond it must be long enough too.
    if (anchor != end && i > anchor + 1 && ground[i - 1] == 0 && long_ground_from(cloud, ground, i, end))
      fill_between(cloud, anchor, i, ground);
    long_stretch = long_stretch || apart(cloud, start, i, p_.shadow_anchor_m);
    if (long_stretch) anchor = i;
  }
}

// The returns between ground returns a and b (same ring) become ground when every refused
// one lies within shadow_band_m of the line joining a and b (by column); the foot of a wall
// within steep_band_m of it, as on the profile.
void ColumnProfiles::fill_between(const Cloud& cloud, Index a, Index b,
                                  std::vector<std::uint8_t>& ground) const {
  const float z0 = cloud.z[a], z1 = cloud.z[b];
  const float span = static_cast<float>(cloud.column[b] - cloud.column[a]);
  for (Index k = a + 1; k < b; ++k) {
    const float t = static_cast<float>(cloud.column[k] - cloud.column[a]) / span;
    const float band = shadowed_[k] == kFoot ? p_.steep_band_m : p_.shadow_band_m;
    if (ground[k] == 0 && std::abs(cloud.z[k] - (z0 + t * (z1 - z0))) > band) return;
  }
  std::fill(ground.begin() + static_cast<std::ptrdiff_t>(a) + 1,
            ground.begin() + static_cast<std::ptrdiff_t>(b), std::uint8_t{1});
}

// Whether the ground returns of the run from i (before `end`) reach shadow_anchor_m from it.
inline bool ColumnProfiles::long_ground_from(const Cloud& cloud, const std::vector<std::uint8_t>& ground,
                                      Index i, Index end) const {
  for (Index j = i; j < end && ground[j] != 0; ++j) {
    if (apart(cloud, i, j, p_.shadow_anchor_m)) return true;
  }
  return false;
}

// Whether each return of [0, end) is continuous with the next one (run_column_gap,
// run_gap_m + run_gap_per_m x range): one pass without branches, so that the compiler
// vectorises it (the ring runs read it only within a ring).
void ColumnProfiles::mark_continuous(const Cloud& cloud, Index end) {
  continuous_.resize(end);
  const std::uint16_t* column = cloud.column.data();
  const float *range = cloud.range_xy.data(), *z = cloud.z.data();
  const int column_gap = p_.run_column_gap;
  const float gap_m = p_.run_gap_m, gap_per_m = p_.run_gap_per_m;
  std::uint8_t* continuous = continuous_.data();
  for (Index a = 0; a + 1 < end; ++a) {
    const float dr = range[a + 1] - range[a], dz = z[a + 1] - z[a];
    const float limit = gap_m + gap_per_m * range[a];
    continuous[a] = static_cast<std::uint8_t>((column[a + 1] - column[a] <= column_gap) &
                                              (dr * dr + dz * dz <= limit * limit));
  }
}

// Whether return a and the ring's next one, not continuous (mark_continuous), are so but
// for one more dropped column, both more than drop_m over the sensor: a tree crown met by
// rising rays drops returns (foliage); lower down real rings drop out on dark asphalt, and a
// road arc (or the floor under a sensor standing on it, vlp16_dual_close_range) merged
// across its drop-outs would make short runs open at both ends.
bool ColumnProfiles::bridged_over_sensor(const Cloud& cloud, Index a) const {
  const float over = p_.sensor_z + p_.drop_m;  // clearly over: not a floor the sensor stands on
  if (cloud.z[a] <= over || cloud.z[a + 1] <= over) return false;
  return cloud.column[a + 1] - cloud.column[a] == p_.run_column_gap + 1 &&
         close_in_range_and_height(cloud, a, a + 1, run_gap(cloud.range_xy[a]));
}

// Run [a, b] of one ring (positions first..last): short, and both ends open to the sky or
// to returns behind it.
bool ColumnProfiles::stands_out(const Cloud& cloud, Index first, Index last, Index a,
                                Index b) const {
  const float extent = std::hypot(cloud.x[b] - cloud.x[a], cloud.y[b] - cloud.y[a]);
  if (extent > p_.silhouette_max_m) return false;
  int gap_a = 0, gap_b = 0;
  const Index before = beyond_end(cloud, first, last, a, false, gap_a);
  const Index after = beyond_end(cloud, first, last, b, true, gap_b);
  return end_open(cloud, a, before, gap_a) && end_open(cloud, b, after, gap_b);
}

// The ring's return beyond run end `end` (positions first..last): the next one (`after`)
// or the one before, or kNone at the frame's edge. `gap` is set to the columns without a
// return between `end` and it; at the frame's edge, to those up to the ring's return across
// it (its first or last one) where the frame is a whole rotation there (the two returns'
// azimuths as close as their column gap says), else up to the edge, beyond which nothing is
// known. Across the edge only the gap counts (the sky): the vehicle moved between the two
// ends of the rotation, so their ranges do not compare.
std::size_t ColumnProfiles::beyond_end(const Cloud& cloud, Index first, Index last, Index end,
                                       bool after, int& gap) const {
  const int columns = static_cast<int>(column_start_.size()) - 1;
  const int column = cloud.column[end];
  if (after ? end + 1 < last : end > first) {
    const Index beyond = after ? end + 1 : end - 1;
    gap = std::abs(static_cast<int>(cloud.column[beyond]) - column) - 1;
    return beyond;
  }
  gap = after ? columns - 1 - column : column;
  const Index across = after ? first : last - 1;
  if (across == end) return kNone;
  const int around = (after ? cloud.column[across] + columns - column
                            : column + columns - cloud.column[across]) - 1;
  const float ex = cloud.x[end] - p_.sensor_x, ey = cloud.y[end] - p_.sensor_y;
  const float ox = cloud.x[across] - p_.sensor_x, oy = cloud.y[across] - p_.sensor_y;
  const float cos_apart = (ex * ox + ey * oy) / (std::hypot(ex, ey) * std::hypot(ox, oy));
  const float step_rad = 2.f * std::numbers::pi_v<float> / static_cast<float>(columns);
  if (cos_apart >= std::cos(kAzimuthSlack * static_cast<float>(around + 1) * step_rad)) gap = around;
  return kNone;
}

// Whether a run's end return `end` opens onto the sky (`gap` columns without a return to
// the ring's next return `beyond`, or to the frame's edge when that is kNone, reach
// sky_columns) or onto a return behind it (farther away).
bool ColumnProfiles::end_open(const Cloud& cloud, Index end, Index beyond, int gap) const {
  if (gap >= p_.sky_columns) return true;  // no return for a while: the sky
  return beyond != kNone && (cloud.range_xy[beyond] > cloud.range_xy[end] + p_.run_gap_m ||
                             stopped_by_face(cloud, end, beyond));
}

// Whether the ray of return `end`, rising over the sensor, passed on where the same ring's
// ray beside it (the ring's next return, `nearer`, fewer than sky_columns columns on, closer
// by more than the ring's run gap) met ground that climbed from its column's last ground
// return more steeply than face_over_ray x its ray.
// Terrain does not let the one ray pass beside a face the other ray met: `end` is an object
// seen past the face's end.
bool ColumnProfiles::stopped_by_face(const Cloud& cloud, Index end, Index nearer) const {
  if (p_.sensor_z <= 0.f || cloud.z[end] <= p_.sensor_z) return false;
  const float r = cloud.range_xy[end];
  if (cloud.range_xy[nearer] >= r - run_gap(r)) return false;
  const Index k = position_[nearer];
  const ColumnPoint& q = points_[k];
  if (q.ground == 0 || q.steep != 0) return false;
  const Index begin = column_start_[cloud.column[nearer]];
  float last_r = 0.f, last_z = start_z_;  // the column's start when no ground return before
  for (Index j = k; j > begin;) {
    if (points_[--j].ground != 0) {
      last_r = points_[j].r;
      last_z = points_[j].z;
      break;
    }
  }
  if (q.r < last_r + p_.min_advance_m) return false;
  const float ray = (q.z - p_.sensor_z) / q.r;
  return (q.z - last_z) / (q.r - last_r) >= p_.face_over_ray * ray;
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

inline void ColumnProfiles::add_to_profile(float r, float z) {
  if (profile_size_ == profile_r_.size()) return;
  profile_r_[profile_size_] = r;
  profile_z_[profile_size_] = z;
  ++profile_size_;
}

// Height of the walked profile at horizontal distance r (its ground returns are in walking
// order, increasing r), linear between the returns around r.
inline float ColumnProfiles::profile_at(float r) const {
  std::size_t k = 1;
  while (k < profile_size_ && profile_r_[k] < r) ++k;
  if (k >= profile_size_) return profile_z_[profile_size_ - 1];
  const float r0 = profile_r_[k - 1], r1 = profile_r_[k];
  const float t = r1 > r0 ? std::clamp((r - r0) / (r1 - r0), 0.f, 1.f) : 1.f;
  return profile_z_[k - 1] + t * (profile_z_[k] - profile_z_[k - 1]);
}

// Whether the ray of `ring` in `column` returned from horizontal distance r or farther
// (no more than reach_slack_m short of it).
inline bool ColumnProfiles::ray_returned_past(Index column, int ring, float r) const {
  return ring_reach_[column * kLasers + static_cast<Index>(ring)] > r - p_.reach_slack_m;
}

// Whether the ray of `ring` in `column` reached horizontal distance r: its return lies no
// more than reach_slack_m short of r, or it has none (the sky) and neither neighbour
// column has one short of r (else it may have dropped out).
inline bool ColumnProfiles::ray_reaches(Index column, int ring, float r) const {
  // The ring's farthest return in column c (0: none).
  const auto far = [&](Index c) { return ring_reach_[c * kLasers + static_cast<Index>(ring)]; };
  const float reach = r - p_.reach_slack_m;
  if (far(column) > 0.f) return ray_returned_past(column, ring, r);
  const Index columns = column_start_.size() - 1;
  const auto short_of = [&](Index c) {
    const float farthest = far(c);
    return farthest > 0.f && farthest <= reach;
  };
  return !(column > 0 && short_of(column - 1)) && !(column + 1 < columns && short_of(column + 1));
}

// Whether the column's next return beyond return k (points [k + 1, end)) bends on the way
// the chord to k did: a chord whose gradient `step` lies `bend` above the profile's (below,
// when negative) crossed terrain curving up (down), which goes on rising at least as
// steeply as the chord (no more steeply). A steep next return, or none, does not.
bool ColumnProfiles::bends_on(Index k, Index end, float step, float bend) const {
  const ColumnPoint& q = points_[k];
  for (Index j = k + 1; j < end; ++j) {
    const ColumnPoint& next = points_[j];
    if (next.r < q.r + p_.min_advance_m) continue;
    const float gradient = (next.z - q.z) / (next.r - q.r);
    if (next.steep != 0 || std::abs(gradient) > p_.max_gradient) return false;
    return bend > 0.f ? gradient >= step : gradient <= step;
  }
  return false;
}

// Whether return k (points [k + 1, end) beyond it) lies over the sensor, met by a rising
// ray, on a surface rising more steeply than that ray: each of the column's next
// rising_ray_returns returns rises from the one before at least as steeply as the ray and
// is not steep. Ground met by a rising ray rises so; a roof or a canopy is met from below.
// Fewer returns do where the column has no more (its higher rings went to the sky) and
// only faces stood between k and the column's last ground return (`past_faces_only`): the
// street seen over a ramp's retaining wall from inside the ramp, the wall hiding every
// lower ring (garage at 5 Hz); not a facade seen past a car and refused returns that climb
// to it (jam_s3). A face's top counts as that face (on_wall_top). A return under the sensor
// is taken only as the near end of level ground rising on over it, or running on from under
// `level_run_top` (rises_on_over_sensor).
bool ColumnProfiles::rises_over_its_ray(Index k, Index end, bool past_faces_only,
                                        float level_run_top) const {
  const ColumnPoint& q = points_[k];
  if (p_.sensor_z <= 0.f) return false;
  if (q.z <= p_.sensor_z) return past_faces_only && rises_on_over_sensor(k, end, level_run_top);
  const float ray = (q.z - p_.sensor_z) / q.r;
  float from_r = q.r, from_z = q.z;
  int seen = 0;
  Index j = k + 1;
  for (; j < end && seen < p_.rising_ray_returns; ++j) {
    const ColumnPoint& next = points_[j];
    if (next.r < from_r + p_.min_advance_m) continue;
    const float gradient = (next.z - from_z) / (next.r - from_r);
    if (next.steep != 0 || gradient > p_.max_gradient || gradient < ray) return false;
    from_r = next.r;
    from_z = next.z;
    ++seen;
  }
  return seen == p_.rising_ray_returns || (past_faces_only && seen > 0 && j == end);
}

// Whether a return at (r, z) lies on the top of the wall whose face the column's last steep
// return (face_r, face_z; face_r < 0: none) met: at most wall_top_m behind it and not under
// it (a ring grazing a retaining wall's coping, garage).
bool ColumnProfiles::on_wall_top(float r, float z, float face_r, float face_z) const {
  return face_r >= 0.f && r >= face_r && r - face_r <= p_.wall_top_m && z >= face_z;
}

// Whether return k, under the sensor and past faces alone, is the near end of level ground
// that rises on over the sensor: the column's next return j rises from it gently (not
// steep, less than shoulder_gradient: level ground, not a hill's flank past a bush, where
// level 2 decides) to over the sensor, where it rises over its ray (rises_over_its_ray,
// past faces alone), bending there by no more than gradient_step, and no later return
// overhangs j (under_overhang), and k does not stand over the level-2 surface where that has
// ground of its own. The street seen over a retaining wall from deep in a ramp, its near
// part lower than the sensor (garage), where level 2 follows the ramp and has no ground of
// its own; not a car's roof seen over a van's side on a measured road, with a truck's box
// or a facade's upper floors beyond it (jam).
// Where k lies under `level_run_top` (the walk's second try, when nothing else took k,
// passes the top of the face in front: the last face's highest return; by default no
// height is), the level ground may also run on under the sensor (each return on rising less than
// level_run_gradient from the one before, with the same bend and overhang checks) to the
// column's last return, or to one over the sensor that rises over its ray or is the last:
// the street seen over a ramp's parapet from a vehicle pitched on the ramp or tilted on its
// mounting, which the street's returns never climb over (garage_s703 tilted, garage_s604).
// A roof past a car's side lies level with the side's highest return or over it (the ray
// that passed over the side falls to it), and two roofs rise more steeply (jam_s604, s704);
// level roofs that pass these are short along their ring (drop_short_level_runs).
bool ColumnProfiles::rises_on_over_sensor(Index k, Index end, float level_run_top) const {
  if (raised_over_level2(k, p_.single_rise_m) && level2_.measured(points_[k].index)) return false;
  const bool under_face_top = points_[k].z < level_run_top;
  Index from = k;
  Index j = next_advancing(k, end);
  if (j == end) return false;
  for (;;) {
    const ColumnPoint &q = points_[from], &on = points_[j];
    const float gradient = (on.z - q.z) / (on.r - q.r);
    if (on.steep != 0 || gradient < 0.f || gradient >= p_.shoulder_gradient) return false;
    for (Index m = j + 1; m < end; ++m)
      if (under_overhang(on, points_[m])) return false;
    const Index beyond = next_advancing(j, end);
    if (beyond != end) {
      const float bend = (points_[beyond].z - on.z) / (points_[beyond].r - on.r) - gradient;
      if (std::abs(bend) > p_.gradient_step) return false;
    }
    // Over the sensor (a run from under the face's top may also end at the column's last
    // return; the loop gets past k only under it).
    if (on.z > p_.sensor_z) {
      return (under_face_top && beyond == end) || rises_over_its_ray(j, end, true);
    }
    if (!under_face_top || gradient >= p_.level_run_gradient) return false;
    if (beyond == end) return true;
    from = j;
    j = beyond;
  }
}

// The column's first return after k at least min_advance_m farther than k (end: none).
Index ColumnProfiles::next_advancing(Index k, Index end) const {
  for (Index j = k + 1; j < end; ++j)
    if (points_[j].r >= points_[k].r + p_.min_advance_m) return j;
  return end;
}

// Whether return k, rising from the column's last ground return at gradient `step` by more
// than the profile may bend up at one return, is the terrain climbing on over the sensor:
// it lies over the sensor (met by a rising ray) on the level-2 surface where that surface has
// ground of its own (on_measured_level2), and the column's next return goes on from it on
// that surface, not steep, bending down by no more than gradient_step. A valley's far side
// behind a convex shoulder, the column's rise there too sudden for the walk (hills_s702,
// hills_s402); not a fence line's top that level 2 was fitted to, under the sensor, nor one
// past which the next ring falls to the ground beyond.
bool ColumnProfiles::climbs_on_level2(Index k, Index end, float step) const {
  const ColumnPoint& q = points_[k];
  if (p_.sensor_z <= 0.f || q.z <= p_.sensor_z || !on_measured_level2(q)) return false;
  const Index j = next_advancing(k, end);
  if (j == end) return false;
  const ColumnPoint& next = points_[j];
  const float gradient = (next.z - q.z) / (next.r - q.r);
  return next.steep == 0 && gradient <= p_.max_gradient && gradient >= step - p_.gradient_step &&
         on_measured_level2(next);
}

// Whether q lies within plane_band_m of the level-2 surface where that surface has ground of
// its own (Level2Coverage::measured).
bool ColumnProfiles::on_measured_level2(const ColumnPoint& q) const {
  return std::abs(q.level2_h) <= p_.plane_band_m && level2_.measured(q.index);
}

// Whether `above`, the column's next return (a higher ring), lies more than overhang_m
// nearer than q and over q's ray at its distance.
bool ColumnProfiles::under_overhang(const ColumnPoint& q, const ColumnPoint& above) const {
  if (above.ring == q.ring || above.r >= q.r - p_.overhang_m) return false;
  const float ray_z = p_.sensor_z + (q.z - p_.sensor_z) * (above.r / q.r);
  return above.z > ray_z;
}

// Whether a later return of the column than k (a higher ring) lies more than overhang_m
// nearer, over k's ray there and level with k (within single_rise_m): k met the far edge of
// a roof or a canopy that the rings over it met from below (a carport on a bank's top).
bool ColumnProfiles::under_level_overhang(Index k, Index end) const {
  const ColumnPoint& q = points_[k];
  for (Index j = k + 1; j < end; ++j) {
    const ColumnPoint& above = points_[j];
    if (std::abs(above.z - q.z) < p_.single_rise_m && under_overhang(q, above)) return true;
  }
  return false;
}

// Whether the kink before return k (a return more than drop_m under the profile that kink
// extrapolated) was an object rather than a bend of the terrain: k stands more than
// single_rise_m over a level-2 surface with ground of its own there, so it is on no lower
// surface either, and the kink had ground of the column before it to go back to (not only
// the start's guess: the street over a ramp's parapet, garage_s2).
bool ColumnProfiles::kink_was_an_object(Index k, Index profile_size_before) const {
  return profile_size_before > 1 && raised_over_level2(k, p_.single_rise_m) &&
         level2_.measured(points_[k].index);
}

// One column outwards from the sensor. The profile is the last ground return (r, z) and
// the gradient dz/dr along the column, starting at the ground under the sensor. Heights over
// the profile go to `height` (by cloud point).
void ColumnProfiles::walk_column(Index column, Index begin, Index end,
                                 const std::vector<float>& plane_height, std::vector<float>& height) {
  if (begin == end) return;
  // The profile starts level under the sensor: at z = 0 when the mounting height is known
  // (the vehicle frame's ground), else on the vehicle's surface. Starting with that
  // surface's gradient was worse on hills (a local tilt extrapolated 10 m).
  float last_r = 0.f;
  float last_z = start_z_;
  float gradient = 0.f;
  float gradient_r = 0.f;  // where the gradient holds (the start: level under the vehicle)
  bool blocked = false;  // an obstacle return since the last ground return
  bool obstacle_seen = false;  // an obstacle return since the start
  bool faces_only = true;  // every obstacle return since the last ground return was steep
  // The last steep obstacle return (r < 0: none since the last ground return): a return on
  // the top of its wall still counts as that face.
  float face_r = -1.f, face_z = 0.f;
  int last_ring = -1;    // ring of the last ground return (-1: the start)
  // The farthest return of the rings below the current one, and of the current ring.
  float lower_far_r = 0.f, lower_far_z = 0.f, ring_far_r = 0.f, ring_far_z = 0.f;
  int ring_now = -1;
  // A ray of a lower ring reaching (r, z) passes under it (its height at r, or its return
  // when a little short of r); the ray of a ring between the last ground return and a
  // climb to (r, z) that reached it would have hit any surface joining them.
  auto under_a_ray = [&](float r, float z, int ring) {
    if (lower_far_r > r - p_.reach_slack_m) {
      const float at = std::min(r, lower_far_r);
      const float ray_z = p_.sensor_z + (lower_far_z - p_.sensor_z) * (at / lower_far_r);
      if (ray_z < z - p_.under_ray_m) return true;
    }
    // A ring between the last ground return and this one (every lower ring before the
    // column's first) whose return lies at this distance or farther passed under this
    // return; one that went to the sky counts only for a climb (a sensor drops a ring's
    // returns on a dark road over whole stretches of columns: vlp16_outdoor_600rpm).
    const bool climbs = z > last_z + p_.sky_climb_m;
    for (int between = last_ring + 1; between < ring; ++between) {
      if (climbs ? ray_reaches(column, between, r) : ray_returned_past(column, between, r)) {
        return true;
      }
    }
    return false;
  };
  // Resuming on a gradient that is only the start's guess, which terrain curvature may have
  // bent over `drift` metres since the point where it holds (resume_curvature_per_m).
  auto resumes_bent = [&](Index k, float step, float drift, float level_run_top) {
    const float bend = step - gradient;
    return profile_size_ <= 2 &&
           std::abs(bend) <= p_.resume_gradient_change + p_.resume_curvature_per_m * std::max(0.f, drift) &&
           ((std::abs(points_[k].level2_h) <= p_.single_rise_m && bends_on(k, end, step, bend)) ||
            rises_over_its_ray(k, end, faces_only, level_run_top));
  };
  profile_size_ = 0;
  add_to_profile(last_r, last_z);
  Index last_ground = end;  // the column's last ground return taken (end: none yet)
  // The walk's state before the last ground return, kept while that return is a kink
  // (kink_was_an_object may take it back); the kink itself is then last_ground.
  struct BeforeKink {
    float last_r, last_z, gradient, gradient_r;
    int last_ring;
    Index profile_size, last_ground;
  };
  BeforeKink before_kink{};
  bool last_kinked = false;
  // The kink was an object: back to the ground before it, past that obstacle.
  auto take_kink_back = [&] {
    ColumnPoint& kink = points_[last_ground];
    kink.ground = 0;
    if (before_kink.last_ground != end &&
        points_[before_kink.last_ground].road_beyond == kink.index) {
      points_[before_kink.last_ground].road_beyond = kNoPoint;
    }
    last_r = before_kink.last_r;
    last_z = before_kink.last_z;
    gradient = before_kink.gradient;
    gradient_r = before_kink.gradient_r;
    last_ring = before_kink.last_ring;
    profile_size_ = before_kink.profile_size;
    last_ground = before_kink.last_ground;
    blocked = true;
    obstacle_seen = true;
    faces_only = false;
    last_kinked = false;
  };
  for (Index k = begin; k < end; ++k) {
    ColumnPoint& q = points_[k];
    const float r = q.r, z = q.z;
    if (q.ring != ring_now) {
      if (ring_far_r > lower_far_r) lower_far_r = ring_far_r, lower_far_z = ring_far_z;
      ring_far_r = 0.f;
      ring_now = q.ring;
    }
    if (r > ring_far_r) ring_far_r = r, ring_far_z = z;
    const float advance = r - last_r;
    // Beyond the last ground return the profile is extrapolated; nearer (a canopy or a
    // wall seen by a higher ring in front of ground already walked), it is interpolated.
    const float over = advance >= 0.f ? z - (last_z + gradient * advance) : z - profile_at(r);
    height[q.index] = over;
    if (q.steep != 0) {  // a wall, a car side, a pole
      // Past an obstacle before the column's first ground return the profile is only the
      // start's guess: its band needs the level-2 surface not to disagree (the foot of a far
      // wall seen past a near one, level with the start by chance).
      const bool guess_off =
          blocked && profile_size_ == 1 && std::abs(q.level2_h) > p_.single_rise_m;
      // (or of a level-1 plane that explains its cell: the foot of a wall on a slope)
      // (before the column's first ground return the profile is only the start's guess;
      // but the column's first return over the start's level is no foot: the lowest ring
      // met a wall over the ground it hides, the plane passing there by chance, garage_s105)
      // Nor where the climb is only a guess (a shed's wall on a bank top the rings never
      // see, where the bank's slope extrapolated runs into it).
      const bool climb_guessed = climb_is_guess(gradient, advance);
      const bool start_guessed = profile_size_ == 1 && (k != begin || over <= 0.f);
      q.ground = (std::abs(over) < p_.steep_band_m && !guess_off && !climb_guessed) ||
                 (std::abs(plane_height[q.index]) < p_.steep_band_m &&
                  (std::abs(over) < p_.plane_foot_m || start_guessed));
      const bool vetoed = under_a_ray(r, z, q.ring);
      if (q.ground != 0 && vetoed) q.ground = 0;
      // The foot of a wall off the profile's band (a post on a crowned road's shoulder): the
      // ring may take it where it runs on level with its ground on both sides (fill_shadows).
      if (q.ground == 0 && !vetoed) q.shadowed = kFoot;
      if (q.ground == 0) face_r = r, face_z = z;
      blocked = true;
      obstacle_seen = true;
      continue;
    }
    if (advance < p_.min_advance_m) {  // over or under ground already walked
      q.ground = over > -p_.label_down_m && over < p_.label_up_m;
      // A ground return a little farther at a plausible gradient moves the profile's end
      // there, keeping its gradient (the rings crowd on a bank face close to the sensor).
      if (q.ground != 0 && advance > 0.f &&
          std::abs(z - last_z) <= p_.max_gradient * advance + p_.anchor_slack_m) {
        last_r = r;
        last_z = z;
        add_to_profile(r, z);
        last_ring = q.ring;
      }
      continue;
    }
    if (last_kinked && over < -p_.drop_m && kink_was_an_object(k, before_kink.profile_size)) {
      take_kink_back();
      --k;  // this return walked again (unsigned wrap-around at 0 is undone by the ++k)
      continue;
    }
    const float step = (z - last_z) / advance;  // gradient from the last ground return
    bool accept = false;
    bool level_run = false;  // taken only as level ground running on past a face
    float next_gradient = 0.f;
    float next_gradient_r = 0.5f * (last_r + r);  // a chord's gradient holds at its middle
    if (over < -p_.drop_m) {  // a lower surface (fields below a levee): level from here
      accept = true;
      // ... unless it still rises from the last ground return, bending no more than at any
      // return: a hill's shoulder, rising on at the measured gradient (also when it rises
      // only gently: a valley's far side rising on behind a convex shoulder, hills_s702).
      const bool rising = step >= p_.shoulder_gradient;
      if (step >= p_.keep_gradient_rise && step >= gradient - p_.gradient_step) {
        next_gradient = step;
      } else {
        next_gradient_r = r;
      }
      // ... but not under an overhang: the next ring of the column met something nearer
      // and over this return's ray there (a tree crown on a bank's top, met from below:
      // ground cannot lie over a ray that passed on under it).
      if (rising && k + 1 < end && under_overhang(q, points_[k + 1])) accept = false;
      if (rising && accept && under_level_overhang(k, end)) accept = false;
      // ... nor the column's last return far past a climb over the sensor: what stands on
      // a top the rings cannot see (past_hidden_top), unless it lies on the level-2 surface
      // where that surface has ground of its own (the climb's hillside rising on, met by
      // the next ring far out: hills_s504, hills_s702).
      if (rising && k + 1 == end && past_hidden_top(r, last_r, last_z) &&
          !on_measured_level2(q)) {
        accept = false;
      }
    } else {
      const float rise = blocked           ? p_.blocked_rise_m + p_.blocked_rise_per_m * advance
                         : profile_size_ == 1 ? p_.start_rise_m + p_.start_rise_per_m * advance
                                              : p_.rise_m + p_.rise_per_m * advance;
      // Past an obstacle the ground may have risen out of sight: a gentle slope from the
      // last ground return is taken (a car roof is a steep step from it).
      // Before any ground return of the column the profile's gradient is only the start's
      // guess: resuming on it needs the level-2 surface not to disagree (a car roof seen
      // past a car side next to the sensor, in a jam), or ground rising over the sensor.
      const auto takes = [&](float level_run_top) {
        const bool on_guess = profile_size_ > 1 || !(std::abs(q.level2_h) > p_.single_rise_m) ||
                              rises_over_its_ray(k, end, faces_only, level_run_top);
        const bool resumes =
            blocked && (std::abs(step - gradient) <= p_.resume_gradient_change
                            ? on_guess
                            : resumes_bent(k, step, 0.5f * (last_r + r) - gradient_r, level_run_top));
        return std::abs(step) <= p_.max_gradient &&
               (over <= rise || resumes || (!blocked && climbs_on_level2(k, end, step)));
      };
      accept = takes(kNoLevelRun);
      if (!accept && blocked && faces_only && z <= p_.sensor_z && face_r >= 0.f) {
        level_run = takes(face_z);
      }
      next_gradient = std::clamp(step, gradient - p_.gradient_step, gradient + p_.gradient_step);
      // Where the climb is only a guess, the profile drawn from the obstacle return deepest
      // under it must take the return too (bank_s1001: a tree crown 20 m past the bank's
      // slope, behind a building whose lowest return the slope extrapolated passes 1.1 m over).
      if (accept && blocked && climb_is_guess(gradient, advance)) {
        const Index from = last_ground == end ? begin : last_ground + 1;
        accept =
            !rises_off_bound(r, z, gradient, deepest_obstacle(from, k, last_r, last_z, gradient));
      }
    }
    // Past an obstacle, a return on a level-1 plane that explains its cell is ground too.
    if (!accept && blocked && std::abs(plane_height[q.index]) <= p_.plane_band_m) accept = true;
    // Else, past faces alone and under the sensor, level ground running on past the face
    // (rises_on_over_sensor), which its ring must then confirm (drop_short_level_runs).
    if (!accept && level_run) accept = true, q.level_run = 1;
    const bool refused_here = !accept;
    if (accept && under_a_ray(r, z, q.ring)) accept = false;
    if (!accept) {
      // Refused only for an obstacle in front (a gentle enough rise, no ray under it):
      // fill_shadows may take it from the ring.
      q.shadowed = refused_here && blocked && std::abs(step) <= p_.max_gradient &&
                           !under_a_ray(r, z, q.ring)
                       ? kShadow
                       : 0;
      blocked = true;
      obstacle_seen = true;
      faces_only = faces_only && on_wall_top(r, z, face_r, face_z);
      continue;
    }
    q.ground = 1;
    // Resumed past an obstacle as ground over the sensor where level 2 disagrees.
    q.rises_on = blocked && profile_size_ <= 2 && !(std::abs(q.level2_h) <= p_.single_rise_m) &&
                 rises_over_its_ray(k, end, faces_only);
    q.kinked = step - gradient > p_.kink_gradient;
    last_kinked = q.kinked != 0;
    if (last_kinked) {
      before_kink = {last_r, last_z, gradient, gradient_r, last_ring, profile_size_, last_ground};
    }
    q.resumed = blocked;
    // Ground level with the ground under the vehicle, no obstacle before it in the column:
    // that ground going on (rule 4 keeps it, whatever the level-2 surface says, when no
    // ground is left before it: a bush in front taken by the walk, then as a silhouette).
    q.vehicle_ground = !obstacle_seen &&
                       std::abs(z - start_z_) <= 0.5f * p_.single_rise_m;
    // A ground return level with the start, no obstacle before it, and this one level with
    // it (a higher ring, nothing between): the vehicle's road going on, seen by two rings.
    if (last_ground != end && !blocked && points_[last_ground].vehicle_ground != 0 &&
        q.ring > points_[last_ground].ring &&
        std::abs(z - last_z) <= 0.5f * p_.single_rise_m) {
      points_[last_ground].road_beyond = q.index;
    }
    last_ground = k;
    last_r = r;
    last_z = z;
    add_to_profile(r, z);
    gradient = next_gradient;
    gradient_r = next_gradient_r;
    blocked = false;
    faces_only = true;
    face_r = -1.f;
    last_ring = q.ring;
  }
}

// Whether a return at distance r, the column's last, lies past the top of a climb over the
// sensor that the walk followed to (last_r, last_z), over more than one ground return (not
// a lone return resumed past an obstacle: the street over a ramp's wall), and more than
// hidden_top_range_ratio times as far. Ground over the sensor is met only by rising rays, where
// it rises more steeply than the ray; a top that levels off hides from every ray past its
// edge, so the next ring's return that far out, with nothing over it, is what stands on
// that top (a shed on a bank's top, bank_s1 and bank_s101): the climb's surface rising on
// shows in the rings over it (hills_s4) or closer behind the edge.
bool ColumnProfiles::past_hidden_top(float r, float last_r, float last_z) const {
  return p_.sensor_z > 0.f && profile_size_ > 2 && last_z > p_.sensor_z &&
         r > p_.hidden_top_range_ratio * last_r;
}

// Whether the profile, extrapolated `advance` past its last ground return with `gradient`,
// climbs more than steep_climb_m there: far past the last ground return on a climbing
// profile the extrapolation is only a guess.
inline bool ColumnProfiles::climb_is_guess(float gradient, float advance) const {
  return gradient * advance > p_.steep_climb_m;
}

// Of the column's returns [from, k) that are no ground and lie past the profile's end (at
// least min_advance_m beyond last_r), the one lying deepest under the profile extrapolated
// from (last_r, last_z) with `gradient` (r < 0: none under it). Out of line, as
// rises_off_bound: only a climb far past its last ground return calls them, and inlined into
// walk_column they cost the detector 0.5 % more instructions (callgrind), out of line 0.3 %.
[[gnu::noinline]] ColumnProfiles::GroundBound ColumnProfiles::deepest_obstacle(
    Index from, Index k, float last_r, float last_z, float gradient) const {
  GroundBound bound;
  for (Index j = from; j < k; ++j) {
    const ColumnPoint& q = points_[j];
    if (q.ground != 0 || q.r < last_r + p_.min_advance_m) continue;
    const float depth = last_z + gradient * (q.r - last_r) - q.z;
    if (depth > bound.depth) bound = {q.r, q.z, depth};
  }
  return bound;
}

// Whether a return at (r, z), taken past obstacles, rises off the profile drawn with its
// gradient from `bound` instead of the last ground return: by more than the allowance past an
// obstacle (rule 2), its gradient from the bound more than resume_gradient_change off the
// profile's. Every return lies at or over the ground at its distance, so the ground there
// is at most the bound's height, where a climb extrapolated far past its last ground return
// (a bank's slope) may run over it.
[[gnu::noinline]] bool ColumnProfiles::rises_off_bound(float r, float z, float gradient,
                                                       const GroundBound& bound) const {
  if (bound.r < 0.f || r < bound.r + p_.min_advance_m) return false;
  const float advance = r - bound.r;
  const float over = z - (bound.z + gradient * advance);
  const float step = (z - bound.z) / advance;
  return over > p_.blocked_rise_m + p_.blocked_rise_per_m * advance &&
         std::abs(step - gradient) > p_.resume_gradient_change;
}

// A ground return of its column that may vouch for its neighbours (rule 4): not on a steep
// surface taken for the foot of a wall.
inline bool ColumnProfiles::is_ground_neighbour(Index k) const {
  return points_[k].ground != 0 && points_[k].steep == 0;
}

// Whether return k lies more than `by` over the level-2 surface.
inline bool ColumnProfiles::raised_over_level2(Index k, float by) const {
  const float h = points_[k].level2_h;
  return std::isfinite(h) && h > by;
}

// Whether a ground return of another column at most refute_lateral_m to the side of column
// c's vertical plane, not raised over the level-2 surface, lies between ground returns a and
// b of column c (in distance) more than single_rise_m under the profile joining them, less
// the rise the steepest ground allows over the lateral distance. Columns are scanned outwards
// until one lies farther to the side than refute_lateral_m at a's distance.
bool ColumnProfiles::rise_refuted(const Cloud& cloud, Index c, Index a, Index b) const {
  constexpr Index kMaxColumns = 64;  // empty columns (sky, drop-outs) scanned past at most
  const ColumnPoint &pa = points_[a], &pb = points_[b];
  const float ux = cloud.x[pa.index] / pa.r, uy = cloud.y[pa.index] / pa.r;
  const auto lateral = [&](const ColumnPoint& q) {
    return std::abs(ux * cloud.y[q.index] - uy * cloud.x[q.index]);
  };
  // 1: column n refutes the rise; -1: it lies too far to the side (stop); 0: go on.
  const auto check = [&](Index n) {
    const Index first = column_start_[n], end = column_start_[n + 1];
    if (first < end && lateral(points_[first]) * pa.r > p_.refute_lateral_m * points_[first].r) {
      return -1;
    }
    for (Index j = first; j < end; ++j) {
      const ColumnPoint& q = points_[j];
      if (q.r <= pa.r || q.r >= pb.r || q.ground == 0) continue;
      if (!(std::abs(q.level2_h) <= 0.5f * p_.single_rise_m)) continue;
      const float side = lateral(q);
      if (side > p_.refute_lateral_m) continue;
      const float profile = pa.z + (q.r - pa.r) / (pb.r - pa.r) * (pb.z - pa.z);
      if (profile - p_.max_gradient * side - q.z > p_.single_rise_m) return 1;
    }
    return 0;
  };
  const Index columns = column_start_.size() - 1;
  const auto refuted_on_side = [&](bool left) {
    for (Index step = 1; step <= kMaxColumns && (left ? step <= c : c + step < columns); ++step) {
      const int verdict = check(left ? c - step : c + step);
      if (verdict != 0) return verdict > 0;
    }
    return false;
  };
  return refuted_on_side(true) || refuted_on_side(false);
}

// A column's profile rising more than single_rise_m from one ground return to the next where
// a neighbouring column saw the ground between them that much lower (rise_refuted): the
// terrain is one height field, and within refute_lateral_m it cannot stand that much higher
// in one column than in the next. The higher return is an object: a fence line the walk took
// past a lower fence, the ground between the two seen through the first one's gaps
// (fences_s103). Decided on the walk's labels, then applied, so the order of the columns
// does not matter.
void ColumnProfiles::drop_refuted_rises(const Cloud& cloud) {
  const Index columns = column_start_.size() - 1;
  refuted_.clear();
  refuted_.reserve(points_.size());  // grown once, with the cloud
  for (Index c = 0; c < columns; ++c) {
    Index last = points_.size();  // the column's last ground return
    for (Index k = column_start_[c]; k < column_start_[c + 1]; ++k) {
      if (!is_ground_neighbour(k)) continue;
      if (last < points_.size() && points_[k].z - points_[last].z > p_.single_rise_m &&
          rise_refuted(cloud, c, last, k)) {
        refuted_.push_back(static_cast<std::uint32_t>(k));
      }
      last = k;
    }
  }
  for (const std::uint32_t k : refuted_) points_[k].ground = 0;
}

// A group of consecutive raised ground returns of a column (over half single_rise_m above
// the level-2 surface), whose members vouch for each other under rule 4, is an object the
// walk climbed and is dropped whole when
// - it lies along at most bump_group_max_m and each member stands more than drop_m over the
//   ground both before it (or the start) and after it (a car roof, a fence top seen by two
//   rings), or
// - it ends the column as an object's top (top_at_column_end).
bool ColumnProfiles::drop_raised_groups(Index begin, Index end) {
  bool dropped_any = false;
  auto raised = [&](Index k) { return raised_over_level2(k, 0.5f * p_.single_rise_m); };
  float before_z = start_z_;
  bool ground_before = false;
  Index k = begin;
  while (k < end) {
    if (!is_ground_neighbour(k) || !raised(k)) {
      if (is_ground_neighbour(k)) before_z = points_[k].z, ground_before = true;
      ++k;
      continue;
    }
    Index last = k, after = k + 1;
    for (; after < end; ++after) {
      if (!is_ground_neighbour(after)) continue;
      if (!raised(after)) break;
      last = after;
    }
    bool drop = after == end && top_at_column_end(k, last, !ground_before);
    if (after < end && points_[last].r - points_[k].r <= p_.bump_group_max_m) {
      const float floor_z = std::max(before_z, points_[after].z) + p_.drop_m;
      drop = true;
      for (Index g = k; g <= last && drop; ++g) {
        drop = !is_ground_neighbour(g) || points_[g].z > floor_z;
      }
    }
    for (Index g = k; g <= last && drop; ++g) {
      if (!is_ground_neighbour(g)) continue;
      points_[g].ground = 0;
      points_[g].dropped = 1;
      dropped_any = true;
    }
    k = after;
  }
  return dropped_any;
}

// Whether any return of [first, last] (ground or not) lies on a steep surface.
bool ColumnProfiles::any_steep(Index first, Index last) const {
  for (Index g = first; g <= last; ++g) {
    if (points_[g].steep != 0) return true;
  }
  return false;
}

// Whether the raised group [first, last] that ends its column (no ground return after it)
// is an object's top the walk took, not confirmed by the column before it either:
// - it resumed past an obstacle, every return more than half single_rise_m over the start
//   (a fence line, a barrier or a car roof seen over the one in front; level with the
//   start it is the vehicle's road going on past a car, a ramp's street level), or
// - it holds the column's first ground returns (`column_first`), met by at most two rings
//   before any return resumed past an obstacle, every return more than drop_m over the
//   start (a barrier's top met by a Puck Hi-Res's two lowest rings, whose ground lies
//   beyond it; three rings or more climbing are a bank's face), or
// - it starts where the profile kinked up from the column's ground (ColumnPoint::kinked),
//   that first return already more than single_rise_m over the level-2 surface, met by at
//   most two rings, every return more than half single_rise_m over the start and none of
//   the group's returns steep: fence lines met one per ring at 17 and 21 m, each taken as a
//   rise from the last, whose rings go on over them to a facade (fences_s704). A bank's face
//   climbed by three rings or more, or with steep returns, is a surface; terrain bending up
//   far out, where the level-2 surface lags, is under it by less at its first return
//   (bank_s804: the far side of a dip);
// and the level-2 surface lies more than single_rise_m under one of its returns where that
// surface was fitted to ground of its own (Level2Coverage: not inherited or extrapolated),
// every return under the sensor (a top met from above lies under the sensor; ground that
// climbs over the sensor's height, a bank's face where the cells lag or the street over a
// ramp's parapet, is met by rising rays).
bool ColumnProfiles::top_at_column_end(Index first, Index last, bool column_first) const {
  const bool resumed = points_[first].resumed != 0;
  const bool kinked = points_[first].kinked != 0 && !column_first && !resumed &&
                     raised_over_level2(first, p_.single_rise_m);
  if (!(resumed || column_first || kinked) || p_.sensor_z <= 0.f) return false;
  if (kinked && any_steep(first, last)) return false;
  const float over_start = resumed || kinked ? 0.5f * p_.single_rise_m : p_.drop_m;
  bool high = false;
  // The column's first ground returns, or the kinked rise's (none resumed past an obstacle).
  int first_returns = 0;
  bool before_resumed = true;
  for (Index g = first; g <= last; ++g) {
    if (!is_ground_neighbour(g)) continue;
    const ColumnPoint& q = points_[g];
    before_resumed = before_resumed && q.resumed == 0;
    if (!resumed && before_resumed && ++first_returns > 2) return false;
    if (q.z - start_z_ <= over_start || q.z >= p_.sensor_z) return false;
    // The cells' state is looked up only for a return that high.
    high = high || (raised_over_level2(g, p_.single_rise_m) && level2_.measured(q.index));
  }
  return high;
}

// Whether cloud point i (strongest layer) lies on a ring run (find_ring_runs) at least min_m
// long, measured along its returns (on across the frame's edge where the run goes on).
bool ColumnProfiles::on_ring_run_of(const Cloud& cloud, Index i, float min_m) const {
  const auto after = std::upper_bound(runs_.begin(), runs_.end(), i,
                                      [](Index p, const RingRun& run) { return p < run.a; });
  if (after == runs_.begin() || i > (after - 1)->b) return false;
  float length = 0.f;
  const auto walk = [&](const RingRun& run) {
    for (Index k = run.a; k < run.b && length < min_m; ++k) {
      length += std::hypot(cloud.x[k + 1] - cloud.x[k], cloud.y[k + 1] - cloud.y[k]);
    }
  };
  walk(*(after - 1));
  if ((after - 1)->wrap != kNoRun) walk(runs_[(after - 1)->wrap]);
  return length >= min_m;
}

// A ground return raised over the level-2 surface (by single_rise_m, or by kink_rise_m when
// it bent the profile up by more than kink_gradient) needs a raised ground neighbour in its
// column (the ground return before or after it along the profile; a return on a steep
// surface taken for the foot of a wall does not count).
void ColumnProfiles::check_single_rises(const Cloud& cloud, Index begin, Index end) {
  Index previous = end;  // previous ground return of the column
  for (Index k = begin; k < end; ++k) {
    if (!is_ground_neighbour(k)) continue;
    const float rise = points_[k].kinked != 0 ? p_.kink_rise_m : p_.single_rise_m;
    if (raised_over_level2(k, rise)) {
      Index next = k + 1;
      while (next < end && !is_ground_neighbour(next)) ++next;
      const bool both = previous < end && next < end;
      // Height over the chord joining the ground returns before and after it.
      const float over_chord = both ? [&] {
        const ColumnPoint &a = points_[previous], &b = points_[next], &q = points_[k];
        const float t = b.r > a.r ? std::clamp((q.r - a.r) / (b.r - a.r), 0.f, 1.f) : 0.f;
        return q.z - (a.z + t * (b.z - a.z));
      }() : 0.f;
      // A bump standing out of both: more than single_rise_m higher over the level-2
      // surface than each of them, and more than drop_m over their chord (a bush on fields
      // that the level-2 cells lie under by an offset: its neighbours are raised by that
      // offset, the bush by its height more). Raised neighbours then do not vouch for it.
      const float h = points_[k].level2_h;
      const bool bump = both && over_chord > p_.drop_m &&
                        h - points_[previous].level2_h > p_.single_rise_m &&
                        h - points_[next].level2_h > p_.single_rise_m;
      const bool before =
          !bump && previous < end && raised_over_level2(previous, 0.5f * p_.single_rise_m);
      // A return that kinked the profile up is vouched for only by a raised return close
      // beyond it (the same rise going on), not by one far beyond (a ring-7 return 40 m past
      // a fence line, where the level-2 surface is extrapolated), unless it resumed as ground
      // over the sensor that the next returns rise on from (rises_over_its_ray: rings near
      // the horizon land far apart).
      const bool vouches_after = points_[k].kinked == 0 || points_[k].rises_on != 0 ||
                                 (next < end && points_[next].r - points_[k].r <=
                                                    p_.kink_vouch_span * points_[k].r);
      const bool after = !bump && next < end && vouches_after &&
                         raised_over_level2(next, 0.5f * p_.single_rise_m);
      // Level with the ground return before it, or under it, the level-2 surface is what
      // is off (a levee's shoulder over a cell fitted to the fields below); past an
      // obstacle only when it is also level with the ground under the vehicle (the road
      // going on past a car): else the level-2 surface may have seen the terrain fall away
      // where the column did not (a tree crown in a valley over a car, hills_s2). With no ground
      // return before it, the column has only the start: the return must be level with the
      // ground under the vehicle (not under it: a bush in the fields below a levee is), no
      // obstacle before it (past a car, a roof may be level with the road).
      const bool level = previous < end
                             ? points_[k].z - points_[previous].z <= 0.5f * p_.single_rise_m &&
                                   (points_[k].resumed == 0 ||
                                    std::abs(points_[k].z - start_z_) <= 0.5f * p_.single_rise_m)
                             : points_[k].vehicle_ground != 0;
      // On or under the chord joining the ground returns before and after it, it is no
      // bump in the column (a fence line stands over that chord by its height).
      const bool on_chord = both && over_chord <= 0.5f * p_.single_rise_m;
      // Over the sensor, where level 2 only extrapolates, a long ring run is the terrain
      // climbing on (the cells lag it), not an object standing on it.
      const auto climbing_run = [&] {
        const ColumnPoint& q = points_[k];
        return q.z >= p_.sensor_z && !level2_.measured(q.index) &&
               on_ring_run_of(cloud, q.index, p_.rise_run_min_m);
      };
      if (!before && !after && !level && !on_chord && !climbing_run()) {
        points_[k].ground = 0;
        // Under the ground the vehicle stands on, the ring may still take it (fill_shadows):
        // terrain falling away (a levee's side grazed by a ring) runs on along the ring from
        // ground to ground, where a fence or a bush stands out of it.
        points_[k].shadowed = points_[k].z < start_z_ ? kShadow : 0;
      }
    }
    previous = k;
  }
}

// A steep return the walk took as a wall's foot on the profile through a ground return that
// was then dropped as a raised group (drop_raised_groups: a barrier's top met by ring 0, its
// face by the rings over it) stood on that object: no ground unless a ground return the
// column kept lies between them. (Also after a dropped single rise it cost more than it
// bought: a valley's side under a lagging level 2, hills_s702.)
void ColumnProfiles::drop_orphaned_feet(Index begin, Index end) {
  bool orphaned = false;  // a ground return dropped since the last one kept
  for (Index k = begin; k < end; ++k) {
    ColumnPoint& q = points_[k];
    if (q.steep == 0) {
      if (q.ground != 0) orphaned = false;
      orphaned = orphaned || q.dropped != 0;
    } else if (orphaned) {
      q.ground = 0;
    }
  }
}

}  // namespace vlpground::detail
