// Level 3 along the rings (docs/detector.md, "Column profiles", rule 5): runs of returns
// continuous along each ring, and the runs standing out of the terrain as objects
// (silhouettes).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "column_profile.hpp"

namespace vlpground::detail {

using Index = std::size_t;

namespace {
// Whether returns a and b lie within `limit` of each other in horizontal range and height
// (the run gap's test; mark_continuous does the same inline, vectorised).
bool close_in_range_and_height(float dr, float dz, float limit) {
  return dr * dr + dz * dz <= limit * limit;
}
bool close_in_range_and_height(const Cloud& cloud, std::size_t a, std::size_t b, float limit) {
  return close_in_range_and_height(cloud.range_xy[b] - cloud.range_xy[a], cloud.z[b] - cloud.z[a],
                                   limit);
}

// The columns without a return between returns a and b of one ring (either order, on the
// same side of the frame's edge).
int columns_between(const Cloud& cloud, std::size_t a, std::size_t b) {
  return std::abs(static_cast<int>(cloud.column[b]) - static_cast<int>(cloud.column[a])) - 1;
}
}  // namespace

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
  const int columns = frame_columns();
  const int gap =
      static_cast<int>(cloud.column[start]) + columns - static_cast<int>(cloud.column[end]);
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
    if (!stands_out(cloud, run.first, run.last, outer_a, run.b) &&
        !(p_.continues_previous && stands_out_with_past(cloud, run))) {
      continue;
    }
    if (before != nullptr) mark_standing_out(*before);
    mark_standing_out(run);
  }
  mark_broken_silhouettes(cloud);
  mark_chained_silhouettes(cloud);
  mark_silhouettes_across_objects(cloud);
  mark_hidden_silhouettes(cloud);
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
  const int columns = frame_columns();
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
    if (out_two && two_nearer) {
      together = outer_end_sky(cloud, one, false) && runs_raised(i, i);
    } else if (out_one && !two_nearer) {
      together = outer_end_sky(cloud, two, true) && runs_raised(j, j);
    }
    if (!together) continue;
    mark_standing_out(one);
    mark_standing_out(two);
  }
}

// A ring line that small cuts broke into several runs (a tree crown's foliage drops a
// column here and there, its edge steps in and out) stands out whole: runs joined across
// small cuts (joined_across_small_cut), at least one of them a dropped column, the whole
// at most silhouette_max_m long and open at both outer ends (the sky or farther returns),
// and either every part more than single_rise_m over the level-2 surface at both its ends
// or the next ring up meeting the line's own face over it and nothing farther
// (face_over_line: where the level-2 surface lies on the crowns, hills_s2104), or the ring
// falling out of reach past both outer ends (sky_past_both_ends). Tree crowns over a valley
// past a crest, level with the vehicle's ground (hills_s1005, hills_s1301,
// hills_s2104): no part stands out alone or meets the sky where it is cut. Without the
// dropped column, the ground on a bank's top behind bushes, cut only by their steps in
// range, stood out (bank_s1505 at 5 Hz: F1 -0.0034). With neither of the last two checks,
// fences lose ground seen through their gaps and the real outdoor drive
// (vlp16_outdoor_600rpm) changes 98 labels instead of 5: a real ring's drop-outs on dark
// ground cut it alike. Taking the sky over the line as a face too would also take such a
// road arc where the next ring sees nothing (more crowns in hills_s1901, but not built).
void ColumnProfiles::mark_chained_silhouettes(const Cloud& cloud) {
  for (std::size_t i = 0, j = 0; i < runs_.size(); i = ++j) {  // runs_[i..j]: one chain
    bool dropped = false;  // a column dropped at one of the cuts
    for (; j + 1 < runs_.size() && joined_across_small_cut(cloud, j); ++j) {
      dropped = dropped || cloud.column[runs_[j + 1].a] - cloud.column[runs_[j].b] > 1;
    }
    const RingRun &first = runs_[i], &last = runs_[j];
    if (!dropped || !stands_out(cloud, first.first, first.last, first.a, last.b) ||
        !(runs_raised(i, j) || sky_past_both_ends(cloud, first, last) ||
          face_over_line(cloud, first, last))) {
      continue;
    }
    for (std::size_t k = i; k <= j; ++k) mark_standing_out(runs_[k]);
  }
}

// A short ring line that a nearer object in front cuts in two stands out whole: the ring's
// runs on either side of the object (run_past_object), neither level with the vehicle's
// ground, the whole a silhouette with the sky at both outer ends (stands_out_across_object).
// Each part alone meets the object at one end, so it does not stand out, and neither is a
// hidden run (mark_hidden_silhouettes): past the object the ring comes out where it went in.
// Fresh bank_s6401 tilted: ring 9 meets an object 1.1 m tall, 29-32 m out on a bank's top
// that ring 8 met 14-15 m out, cut by a low object 16.9 m out, the sky on both sides (0.98 %
// -> 0 high obstacles as ground); hills_s6401 at 20 Hz: ring 10 on a tree crown 25.5 m out
// cut by a nearer branch. The road between two parked cars seen by ring 1 past a third
// (jam_s1003) is level with the vehicle's ground and stays.
void ColumnProfiles::mark_silhouettes_across_objects(const Cloud& cloud) {
  if (p_.sensor_z <= 0.f) return;
  for (std::size_t i = 0; i + 2 < runs_.size(); ++i) {
    if (stands_out_[runs_[i + 1].a] == 0) continue;  // no object after run i
    const std::size_t j = run_past_object(cloud, i);
    if (j == kNoRun) continue;
    const RingRun &one = runs_[i], &two = runs_[j];
    if (!stands_out_across_object(cloud, one, two) || level_with_start(one) ||
        level_with_start(two)) {
      continue;
    }
    mark_standing_out(one);
    mark_standing_out(two);
  }
}

// The ring's run after run i past an object in front, where the ring goes on there from run
// i: runs standing out between them, every return nearer than both ends of the cut, no sky
// among them, and the run's first return within twice the run gap of run i's last (as the
// ring comes out behind an object, hidden_by_object); kNoRun where there is none.
std::size_t ColumnProfiles::run_past_object(const Cloud& cloud, std::size_t i) const {
  const RingRun& one = runs_[i];
  if (one.wrap != kNoRun || one.b + 1 >= one.last) return kNoRun;
  std::size_t j = i + 1;
  while (j < runs_.size() && runs_[j].first == one.first && stands_out_[runs_[j].a] != 0) ++j;
  if (j == i + 1 || j == runs_.size() || runs_[j].first != one.first || runs_[j].wrap != kNoRun) {
    return kNoRun;
  }
  const Index start = runs_[j].a;
  const float* const range = cloud.range_xy.data();
  if (!close_in_range_and_height(range[start] - range[one.b], cloud.z[start] - cloud.z[one.b],
                                 2.f * run_gap(range[one.b]))) {
    return kNoRun;
  }
  const float cut_m = std::min(range[one.b], range[start]);
  for (Index k = one.b + 1; k <= start; ++k) {
    if ((k < start && !farther(range[k], cut_m)) ||
        columns_between(cloud, k - 1, k) >= p_.sky_columns) {
      return kNoRun;
    }
  }
  return j;
}

// Whether the ring line from run `one` across an object to run `two` is a silhouette: at
// most silhouette_max_m long with the sky at both outer ends, turning less than half a turn
// round the sensor (as stands_out asks), its ends and the cut within wide_silhouette_range_m, and
// each outer end over the sensor far past its column's ground return of the ring below
// (far_past_lower_ground). The guards come from the tuning set: far hill tops against the sky
// (bank_s5004 at 20 Hz: ring 9 76 m out); a hill's top 32-34 m out past ring 10's ground 23 m out,
// behind a tree (hills_s501 tilted); terrain between tree trunks, where an end opening onto a
// farther return is the ring going on 0.8 m farther (hills_s803 tilted).
bool ColumnProfiles::stands_out_across_object(const Cloud& cloud, const RingRun& one,
                                              const RingRun& two) const {
  for (const Index end : {one.a, one.b, two.b}) {
    if (cloud.range_xy[end] > p_.wide_silhouette_range_m) return false;
  }
  for (const Index end : {one.a, two.b}) {
    if (cloud.z[end] > p_.sensor_z && !far_past_lower_ground(cloud, end)) return false;
  }
  return !apart(cloud, one.a, two.b, p_.silhouette_max_m) && outer_end_sky(cloud, one, false) &&
         outer_end_sky(cloud, two, true) && turns_under_half(cloud, one.a, two.b);
}

// Whether run i and the ring's next run (on the same side of the frame's edge), both under
// the sensor, are one ring line cut small: fewer columns missing than the sky takes, the
// ends within twice the run gap (as mark_broken_silhouettes cuts).
bool ColumnProfiles::joined_across_small_cut(const Cloud& cloud, std::size_t i) const {
  const RingRun& one = runs_[i];
  if (one.b + 1 >= one.last || one.wrap != kNoRun || runs_[i + 1].wrap != kNoRun) return false;
  const Index end = one.b, start = runs_[i + 1].a;
  if (cloud.z[end] >= p_.sensor_z || cloud.z[start] >= p_.sensor_z) return false;
  return columns_between(cloud, end, start) < p_.sky_columns &&
         !apart(cloud, end, start, 2.f * run_gap(cloud.range_xy[end]));
}

// Whether the ring line from run `first` to run `last` opens onto the sky at both outer
// ends (sky_columns or more columns without a return) and past each the ring's next return
// lies farther than the end or more than drop_m under it, with the mounting height known:
// under the sensor a falling ray meets nothing only past terrain falling out of its reach,
// and the line stands alone over it. hills_s6505 (fresh seeds 6501-6505): ring 2 on an
// object 0.6-0.8 m tall, 16 m out on a hillside steepening downwards, where the level-2
// surface lies on the object; a 2-column drop-out cuts the line, and past 10 and 14 columns
// of sky the ring meets returns 17.5 m and 47 m out (1.18 % of the capture's high obstacles
// as ground -> 0.49 %). A real ring's drop-outs on dark ground end where the ring comes back
// at the line's range and height; the sky alone at both ends dropped such lines in the unit
// tests. The real captures run without the mounting height (vlp16_outdoor_600rpm).
bool ColumnProfiles::sky_past_both_ends(const Cloud& cloud, const RingRun& first,
                                        const RingRun& last) const {
  if (p_.sensor_z <= 0.f) return false;
  const auto falls_out = [&](Index end, bool after) {
    const RingBeyond beyond = beyond_end(cloud, last.first, last.last, end, after);  // one ring
    return beyond.gap >= p_.sky_columns && beyond.index != kNone &&
           (farther(cloud.range_xy[end], cloud.range_xy[beyond.index], beyond.across) ||
            cloud.z[end] - cloud.z[beyond.index] > p_.drop_m);
  };
  return falls_out(first.a, false) && falls_out(last.b, true);
}

// Whether every run of runs_[i..j] lies more than single_rise_m over the level-2 surface at
// both its ends.
bool ColumnProfiles::runs_raised(std::size_t i, std::size_t j) const {
  for (std::size_t k = i; k <= j; ++k) {
    if (!raised_over_level2(position_[runs_[k].a], p_.single_rise_m) ||
        !raised_over_level2(position_[runs_[k].b], p_.single_rise_m)) {
      return false;
    }
  }
  return true;
}

// Whether the next ring up meets the face of the ring line from run `first` to run `last`
// over it (at most twice the run gap nearer than its farthest return, more than
// single_rise_m over its highest) in some of its columns and nothing farther in any: an
// object's face, as a tree crown's over its lower edge. Over ground the next ring meets the
// ground farther on, or the sky where a real ring's drop-outs on dark asphalt at range look
// alike. The height keeps a floor the sensor stands on, which the next ring meets a few
// centimetres farther (vlp16_dual_close_range with --min-sensor-height 0: 8.6 -> 7.1 %
// ground without it).
bool ColumnProfiles::face_over_line(const Cloud& cloud, const RingRun& first,
                                    const RingRun& last) const {
  float farthest = 0.f, highest = -std::numeric_limits<float>::infinity();
  for (Index n = first.a; n <= last.b; ++n) {
    farthest = std::max(farthest, cloud.range_xy[n]);
    highest = std::max(highest, cloud.z[n]);
  }
  const float gap = run_gap(farthest);
  const float beyond = farthest + gap, face_from = farthest - 2.f * gap;
  const int above = cloud.ring[first.a] + 1;
  bool face = false;  // the next ring meets the line's own face in some column
  for (Index c = cloud.column[first.a]; c <= cloud.column[last.b]; ++c) {
    for (Index k = column_start_[c]; k < column_start_[c + 1]; ++k) {
      if (points_[k].ring != above) continue;
      if (points_[k].r > beyond) return false;
      face = face || (points_[k].r > face_from && points_[k].z > highest + p_.single_rise_m);
    }
  }
  return face;
}

// A short run that opens onto the sky or farther returns at one end and, at the other,
// meets a nearer run standing out (an object in front of it, the ring past that object not
// going on from the run: hidden_by_object) stands out too: the object hides where the run
// goes on, and its open end is what a silhouette shows. Objects past a grade change met by
// one ring beside one another (slope_s1201 at 20 Hz: boxes 31 m out, 0.56 m over the slope
// falling away, one end at the sky, the other behind a box 16 m out) and fence lines hidden
// at one end by a nearer fence's post or a bush. Over the sensor only a run at one range
// (at_one_range): an object's face across the ring (hills_s603 at 20 Hz: ring 9 on an
// object 37 m out, 1 m over a hill climbing past the sensor's height, beside a nearer one),
// where a ring tracing terrain sideways recedes along it (bank_s1805 tilted: ring 10 on a
// bank's top, 17 -> 23 m out between two bushes). A run with a return level with the ground
// under the vehicle stays: the road between two parked cars, joined by the ring to the
// lower one's side (jam), unless the ring past its open end falls away onto an object far
// under it (falls_away_past). Marked again while runs are added, until none is: each one
// found may hide the next, and chains run long (cars one behind the other down a ramp, an
// object's edge stepping back column by column, each step a run of its own). A mark only
// helps hide another run, so the marks found do not depend on the order; the passes
// alternate direction along the rings so that a chain either way takes few. Only with the
// mounting height known: the ground under the vehicle is then z = 0, not the level-2
// surface's guess (the real captures, run without it, lose a ring's runs between bushes on
// rising terrain: vlp16_outdoor_600rpm).
void ColumnProfiles::mark_hidden_silhouettes(const Cloud& cloud) {
  if (p_.sensor_z <= 0.f) return;
  const std::size_t runs = runs_.size();
  for (bool added = true, forward = true; added; forward = !forward) {
    added = false;
    for (std::size_t n = 0; n < runs; ++n) {
      const RingRun& run = runs_[forward ? n : runs - 1 - n];
      if (stands_out_[run.a] == 0 && hidden_run(cloud, run)) {
        mark_standing_out(run);
        added = true;
      }
    }
  }
}

// Whether run `run` (not standing out) is hidden at one end by an object in front and opens
// at the other (mark_hidden_silhouettes).
bool ColumnProfiles::hidden_run(const Cloud& cloud, const RingRun& run) const {
  const bool over_sensor = cloud.z[run.a] >= p_.sensor_z || cloud.z[run.b] >= p_.sensor_z;
  if (run.wrap != kNoRun || apart(cloud, run.a, run.b, p_.silhouette_max_m) ||
      (over_sensor && !at_one_range(cloud, run))) {
    return false;
  }
  const RingBeyond before = beyond_end(cloud, run.first, run.last, run.a, false);
  const RingBeyond after = beyond_end(cloud, run.first, run.last, run.b, true);
  // The open end first: hidden_by_object walks the ring past the object in front.
  const bool open_a = end_open(cloud, run.a, before) &&
                      hidden_by_object(cloud, run.first, run.last, run.b, after, true);
  const bool open_b = !open_a && end_open(cloud, run.b, after) &&
                      hidden_by_object(cloud, run.first, run.last, run.a, before, false);
  if (!open_a && !open_b) return false;
  // Walked only for a hidden run.
  const Index open_end = open_a ? run.a : run.b;
  const RingBeyond& open_beyond = open_a ? before : after;
  return !level_with_start(run) || falls_away_past(cloud, open_end, open_beyond) ||
         falls_out_of_reach_past(cloud, run, open_end, open_beyond);
}

// Whether the ring past run end `end` (its return `beyond`) meets an object more than
// drop_m under it: a return the column walk did not take as ground, or one standing out.
// The terrain under that object lies lower still, out of the ring's reach: a run level
// with the vehicle's ground there is no road going on but an object's face the ring met at
// its level-ground range, past a grade change where the slope falls away (slope_s6103:
// ring 6 on a van 36.8 m out, 1.4 m over the slope, beside a nearer box; past the van the
// sky, then an object 3.2 m tall 58 m out). The road beside a car on an embankment meets
// the fields far below past it, taken as ground (embankment_s901 tilted).
bool ColumnProfiles::falls_away_past(const Cloud& cloud, Index end,
                                     const RingBeyond& beyond) const {
  if (beyond.index == kNone) return false;
  const Index k = beyond.index;
  return cloud.z[end] - cloud.z[k] > p_.drop_m && (!taken(k) || stands_out_[k] != 0);
}

// Whether the ring past run end `end` (its return `beyond`) goes to the sky over at least
// twice sky_columns and then meets a return lower than `end`, the run lying at one range
// (at_one_range): a falling ray meeting nothing over a stretch, the terrain past it fell out
// of the ring's reach, and a level run is an object's face met at the ring's level-ground
// range past a grade change (slope_s6603: ring 6 on an object 36 m out, 0.77 m over the
// slope, a nearer box at its other end; past it the sky over 189 columns, then the slope
// 0.32 m lower 42 m out, no object that falls_away_past would ask for). Terrain seen by the
// ring to where it falls away recedes towards the sky (hills_s903 at 5 Hz: a hillside 33.8
// -> 36.3 m out, the sky over 28 columns, the hill 0.35 m lower past it), and a drop-out
// of a few columns is no sky to go by.
bool ColumnProfiles::falls_out_of_reach_past(const Cloud& cloud, const RingRun& run, Index end,
                                             const RingBeyond& beyond) const {
  return beyond.index != kNone && beyond.gap >= 2 * p_.sky_columns &&
         cloud.z[beyond.index] < cloud.z[end] && at_one_range(cloud, run);
}

// Whether run `run`'s returns lie within one run gap in range of its nearest.
bool ColumnProfiles::at_one_range(const Cloud& cloud, const RingRun& run) const {
  return at_one_range(cloud, run.a, run.b);
}

// ... returns [a, b] of one ring.
bool ColumnProfiles::at_one_range(const Cloud& cloud, Index a, Index b) const {
  const RangeSpread spread = range_spread(cloud, a, b);
  return spread.farthest - spread.nearest <= run_gap(spread.nearest);
}

// Whether any return of run `run` lies level with the ground under the vehicle (within
// half single_rise_m of the profiles' start), the run being more than one return: a ring
// meets the level of the vehicle's ground at one range (ring 6 of a VLP-16 at 32.8 m from
// 1.72 m up), and a lone return there, a pixel on the edge of a car seen past a nearer one,
// is no road between two cars (slope_s2405: the ring meets nothing else there, the road
// falling away out of its reach).
bool ColumnProfiles::level_with_start(const RingRun& run) const {
  if (run.a == run.b) return false;
  for (Index i = run.a; i <= run.b; ++i) {
    if (std::abs(points_[position_[i]].z - start_z_) <= 0.5f * p_.single_rise_m) return true;
  }
  return false;
}

// Whether a run's end `end` meets, `gap` columns on, a nearer return `beyond` standing out,
// and the ring past that object does not go on from `end`: terrain passing behind a tree
// trunk comes out on its other side within twice the run gap of where it went in
// (hills_s1802 at 20 Hz: a valley's floor 32 m out behind a trunk 15 m out). While passing
// the object, the ring is followed across the frame's edge where the frame is a whole
// rotation there (across_edge), with the motion slack (kEdgeMotionSlack) on its ranges:
// frames are cut straight ahead, where a car in the vehicle's lane hides one behind it
// (jam), and cars stand one behind the other on a ramp falling away out of the rings'
// reach (slope_s2703). Past the object, nearer ground across the edge is not followed: on
// a hill's side the ring runs on nearer all around (hills_s1902 at 20 Hz). Where the ring
// goes to the sky at the object's far end (sky_columns or more without a return), the run
// is hidden: past a crest an object 35 m out beside a nearer one with the sky beyond it
// (crest_s1001 tilted). Only while still passing the object: past it the walk follows the
// ring on, and the sky far along it says nothing of the run (hills_s5 at 20 Hz). Where the
// ring ends past the object at a speck before the sky (lone_before_sky), it did not come
// out there either.
bool ColumnProfiles::hidden_by_object(const Cloud& cloud, Index first, Index last, Index end,
                                      const RingBeyond& beyond, bool after) const {
  if (beyond.index == kNone || beyond.gap >= p_.sky_columns || stands_out_[beyond.index] == 0 ||
      !farther(cloud.range_xy[beyond.index], cloud.range_xy[end], beyond.across)) {
    return false;
  }
  const float r = cloud.range_xy[end];
  Index i = beyond.index;
  bool across = beyond.across;
  bool passing = true;  // every return walked so far stands out: the object in front
  do {
    if (after ? i + 1 < last : i > first) {
      const Index from = i;
      i = after ? i + 1 : i - 1;
      passing = passing && stands_out_[from] != 0;
      // The ring went to the sky past the object: it did not come out there, whatever it
      // meets farther on (crest_s1001 tilted: another object 19 m out, past the sky).
      if (passing && columns_between(cloud, from, i) >= p_.sky_columns) return true;
    } else {
      int around = 0;
      // Across the frame's edge only while passing the object, once.
      if (across || stands_out_[i] == 0) {
        return !across && lone_before_sky(cloud, first, last, i, after);
      }
      i = across_edge(cloud, first, last, i, after, around);
      if (i == kNone) return false;  // the ring ends behind it
      across = true;
    }
    if (i == end) return false;
  } while (farther(cloud.range_xy[i], r, across));
  return !close_in_range_and_height(cloud.range_xy[i] - r, cloud.z[i] - cloud.z[end],
                                    (across ? kEdgeMotionSlack : 1.f) * 2.f * run_gap(r));
}

// Whether return i, the ring's last before the frame's edge that the walk (`after`) meets,
// lies under the sensor, continuous with neither neighbour, with the sky beyond it
// (sky_columns or more without a return, across the edge too): a speck on an object's
// edge, not the ring coming out from behind the object (slope_s6103 at 5 Hz: a return
// 34.9 m out beside a box 30.2 m out at the frame's edge, the sky across the edge; at
// Hi-Res, 32.9 m out beside one 29.9 m out). Met anywhere along the ring, such a return
// may be terrain the ring came out on, a crest's top (crest_s605 at 20 Hz, hills_s904
// tilted: F1 -0.00002 each); over the sensor, a hill's top 71 m out (bank_s5004 at 20 Hz).
bool ColumnProfiles::lone_before_sky(const Cloud& cloud, Index first, Index last, Index i,
                                     bool after) const {
  if (cloud.z[i] >= p_.sensor_z) return false;
  const bool lone =
      (i == first || continuous_[i - 1] == 0) && (i + 1 >= last || continuous_[i] == 0);
  return lone && beyond_end(cloud, first, last, i, after).gap >= p_.sky_columns;
}

// A fragment of a rotation going on from the previous frame (continues_previous): the
// previous frame saw the same azimuths a rotation earlier. A ring's run at the fragment's
// first column goes on across the cut into that frame's last columns, and one at its last
// column (the end of the data) into that frame's next columns, where the returns there are
// continuous with it (kEdgeMotionSlack: the vehicle moved between them, as across a whole
// rotation's edge). The whole stands out when it is short and opens onto the sky or
// farther returns at both ends. Without this, an object straight ahead in a capture's last
// frame (a fragment of 13-47 columns, cut straight ahead) never stood out (slope_s104).
bool ColumnProfiles::stands_out_with_past(const Cloud& cloud, const RingRun& run) const {
  if (run.wrap != kNoRun) return false;
  const int columns = frame_columns();
  // A run's end this close to the frame's edge is neither open (the sky) nor closed here.
  const bool at_cut = run.a == run.first && cloud.column[run.a] < p_.sky_columns;
  const bool at_end = run.b + 1 == run.last && columns - 1 - cloud.column[run.b] < p_.sky_columns;
  if (!at_cut && !at_end) return false;
  // Each end: open where it goes on into the previous frame, else as stands_out asks.
  const auto end_opens = [&](Index end, bool after, float& part) {
    if (after ? at_end : at_cut) return past_part_open(cloud, end, after, part);
    return end_open(cloud, end, beyond_end(cloud, run.first, run.last, end, after));
  };
  float before = 0.f, after = 0.f;
  if (!end_opens(run.a, false, before) || !end_opens(run.b, true, after)) return false;
  const float extent = std::hypot(cloud.x[run.b] - cloud.x[run.a], cloud.y[run.b] - cloud.y[run.a]);
  return before + extent + after <= p_.silhouette_max_m;
}

std::size_t ColumnProfiles::past_on_ring(int c, int ring) const {
  for (Index k = past_column_start_[static_cast<Index>(c)];
       k < past_column_start_[static_cast<Index>(c) + 1]; ++k) {
    const ColumnPoint& q = past_points_[k];
    if (q.ring == ring && q.index < past_strongest_end_) return k;
  }
  return kNone;
}

bool ColumnProfiles::past_part_open(const Cloud& cloud, Index i, bool forward,
                                    float& extent) const {
  const int columns = past_columns();
  const int ring = cloud.ring[i];
  const int step = forward ? 1 : -1;
  // Where the run meets the previous frame: its return of the ring in the run's end
  // column or up to run_column_gap before it (going on), or its last one before the cut
  // (going back), within run_column_gap columns either way.
  Index k = kNone;
  int c = 0;  // k's column
  for (int tries = 0; tries <= 2 * p_.run_column_gap && k == kNone; ++tries) {
    c = forward ? cloud.column[i] - p_.run_column_gap + tries : columns - 1 - tries;
    if (c >= 0 && c < columns) k = past_on_ring(c, ring);
  }
  if (k == kNone) return false;
  const int gap =
      forward ? std::max(0, std::abs(c - cloud.column[i]) - 1) : columns - 1 - c + cloud.column[i];
  if (gap > p_.run_column_gap ||
      !close_in_range_and_height(cloud.range_xy[i] - past_points_[k].r,
                                 cloud.z[i] - past_points_[k].z,
                                 kEdgeMotionSlack * run_gap(cloud.range_xy[i]))) {
    return false;
  }
  // Along the previous frame's ring while continuous (mark_continuous's test), no farther
  // than a silhouette's length along its arc (the previous frame a whole rotation of
  // `columns`).
  const float step_rad = 2.f * std::numbers::pi_v<float> / static_cast<float>(columns);
  const int start = c;
  int empty = 0;  // columns without a return of the ring since k's
  bool open = false;
  for (int n = c + step; n >= 0 && n < columns && !open; n += step) {
    if (past_points_[k].r * step_rad * static_cast<float>(std::abs(n - start)) >
        p_.silhouette_max_m) {
      return false;
    }
    const Index next = past_on_ring(n, ring);
    if (next == kNone) {
      open = ++empty >= p_.sky_columns;  // the sky
      continue;
    }
    const ColumnPoint &u = past_points_[k], &w = past_points_[next];
    if (empty >= p_.run_column_gap ||
        !close_in_range_and_height(w.r - u.r, w.z - u.z, run_gap(u.r))) {
      if (!farther(u.r, w.r)) return false;  // a return as near or nearer: closed
      open = true;                           // one farther on: open
      continue;
    }
    k = next, c = n, empty = 0;
  }
  if (!open) return false;  // the previous frame's data end inside the run
  extent = past_points_[k].r * step_rad * static_cast<float>(std::abs(c - start));
  return true;
}

// Marks run `run`'s returns as standing out.
void ColumnProfiles::mark_standing_out(const RingRun& run) {
  std::fill(stands_out_.begin() + static_cast<std::ptrdiff_t>(run.a),
            stands_out_.begin() + static_cast<std::ptrdiff_t>(run.b) + 1, std::uint8_t{1});
}

// Whether run `run`'s last end (`after`) or first end opens onto the sky (sky_columns
// columns without a return).
bool ColumnProfiles::outer_end_sky(const Cloud& cloud, const RingRun& run, bool after) const {
  return beyond_end(cloud, run.first, run.last, after ? run.b : run.a, after).gap >= p_.sky_columns;
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

// Whether a run from return a to b (across the frame's edge where b's column is before
// a's) covers less than half the frame's columns: its extent, the chord between its ends,
// then measures it (a ring seen all around but for a gap has close ends too).
bool ColumnProfiles::under_half_turn(const Cloud& cloud, Index a, Index b) const {
  const int columns = frame_columns();
  const int span = static_cast<int>(cloud.column[b]) + columns - static_cast<int>(cloud.column[a]);
  return 2 * span < columns;
}

// Whether a run from return a to b (on one side of the frame's edge, b after a) turns less
// than half a turn round the sensor: the angles from a to its middle return and from there
// to b, each under half a turn, add up to under half. The frame's columns do not measure it
// (a fragment of a rotation has fewer), but a run under half of them turns under half.
bool ColumnProfiles::turns_under_half(const Cloud& cloud, Index a, Index b) const {
  if (2 * (cloud.column[b] - cloud.column[a]) < frame_columns()) return true;
  const Index m = a + (b - a) / 2;
  const auto angle = [&](Index i, Index j) {
    const float ix = cloud.x[i] - p_.sensor_x, iy = cloud.y[i] - p_.sensor_y;
    const float jx = cloud.x[j] - p_.sensor_x, jy = cloud.y[j] - p_.sensor_y;
    return std::atan2(ix * jy - iy * jx, ix * jx + iy * jy);
  };
  return std::abs(angle(a, m) + angle(m, b)) < std::numbers::pi_v<float>;
}

// The run standing out (with its part before the frame's edge, if any) is an object unless
// it carries the road the vehicle stands on (its column's first return level with the start,
// the next ground return of the column going on level behind it and not standing out) over
// shadow_anchor_m of the ring: that road seen over a short stretch (the vehicle near a
// levee's edge, a car beside it), not an object: the next ring passes over a tree crown level
// with the road to the fields, or meets the crown again, standing out as well; over a low
// object a higher ring sees the road only in its gaps.
void ColumnProfiles::remove_silhouette(const Cloud& cloud, const RingRun& run,
                                       const RingRun* before) {
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
  // Where the run is an object and the road behind it, the object alone (not across the
  // frame's edge); else the whole object but for the road seen through gaps in it.
  Index keep_a = kNone, keep_b = kNone;
  const bool keeps_road = before == nullptr && road_behind_object(cloud, run, keep_a, keep_b);
  if (before != nullptr) drop_run(*before, kNone, kNone);
  if (keeps_road) {
    drop_run(run, keep_a, keep_b);
  } else {
    drop_all_but_road_through_gaps(cloud, run);
  }
}

// Where the ring goes on past both ends of run `run` on ground the walk took that does not
// stand out (on the same side of the frame's edge: none for a run across it, whose part
// after the edge is the ring's first run): the returns there, and the run's first and last
// returns the walk refused (BetweenFeet); else none. A low fence's face meets the ground at
// its foot, so where the fence recedes past a ring's ground range the ring runs on from the
// face onto the ground and back onto the next face: fences_s6904 at 20 Hz, rings 0-2 on
// the ground 6.8-9.4 m out between two fences 5-10 m out, each ring's line 3-4 m long.
// Without the guards (half the run gap; only between the run's refused returns) F1 was
// lower on 16 tuning captures: past the ends, a low fence's own returns the walk took
// (fences_s5905 at 5 Hz).
ColumnProfiles::BetweenFeet ColumnProfiles::between_feet(const RingRun& run) const {
  if (run.a == run.first || run.b + 1 >= run.last) return {};
  const Index before = run.a - 1, after = run.b + 1;
  for (const Index past : {before, after}) {
    if (!taken(past) || stands_out_[past] != 0) return {};
  }
  Index first = run.a, last = run.b;  // an object's returns at both ends, mostly
  while (first <= run.b && taken(first)) ++first;
  if (first > run.b) return {};
  while (taken(last)) --last;
  return {before, after, first, last};
}

// Whether return i of a run standing out is the ground between two objects' feet: between
// the run's first and last refused returns, and on the surface the ring goes on along past
// both ends of the run (BetweenFeet): at its range within half the run gap and level with
// it within the walk's 0.15 m (half single_rise_m).
bool ColumnProfiles::on_ground_between_feet(const Cloud& cloud, const BetweenFeet& feet,
                                            Index i) const {
  if (feet.first_refused == kNone || i <= feet.first_refused || i >= feet.last_refused) {
    return false;
  }
  const auto same_surface = [&](Index past) {
    return std::abs(cloud.range_xy[i] - cloud.range_xy[past]) <=
               0.5f * run_gap(cloud.range_xy[past]) &&
           std::abs(cloud.z[i] - cloud.z[past]) <= 0.5f * p_.single_rise_m;
  };
  return same_surface(feet.past_before) && same_surface(feet.past_after);
}

// Run `run`'s returns leave the ground, but for [keep_a, keep_b] (none for kNone).
void ColumnProfiles::drop_run(const RingRun& run, Index keep_a, Index keep_b) {
  for (Index i = run.a; i <= run.b; ++i) {
    if (keep_a == kNone || i < keep_a || i > keep_b) points_[position_[i]].ground = 0;
  }
}

// Run `run`'s returns leave the ground, but for the vehicle's road seen through a gap in the
// object: returns the walk took within the run, going on from a lower ring's road in their
// column level within whole_run_level_m and at most gap_road_reach_m farther
// (goes_on_from_road), where the ring steps back onto them from the object on both sides
// (steps_back). A car's ragged foot 9.3-9.4 m out, the ring seeing the road 9.8 m out
// between its returns, 1.5 m past the ring below (embankment_s3401 tilted). Farther out the
// rings lie metres apart and the road's edge may pass between them: a bush's top over the
// fields 25 m out, level with the lower ring's road 8 m nearer (embankment_s1205 tilted).
void ColumnProfiles::drop_all_but_road_through_gaps(const Cloud& cloud, const RingRun& run) {
  const BetweenFeet feet = between_feet(run);
  // The column's first return (the lowest ring on a car's foot: embankment_s6003 at 5 Hz)
  // goes on from the vehicle's ground, not from a lower ring's road.
  const auto level_road = [&](Index i) {
    if (!taken(i)) return false;
    if (first_in_column(cloud, i)) return std::abs(cloud.z[i] - start_z_) <= p_.whole_run_level_m;
    return goes_on_from_road(cloud, i, p_.whole_run_level_m, p_.gap_road_reach_m);
  };
  Index i = run.a;
  while (i <= run.b) {
    Index end = i;  // [i, end): level road stepped back onto from the run's return before
    // Most of an object's returns fail the cheap test, whether the walk took them, first.
    if (i > run.a && taken(i) && steps_back(cloud, i - 1, i)) {
      while (end <= run.b && level_road(end)) ++end;
    }
    if (end > i && end <= run.b && steps_back(cloud, end, end - 1)) {
      i = end;  // seen through a gap: kept
      continue;
    }
    if (taken(i) && on_ground_between_feet(cloud, feet, i)) {
      ++i;  // the ground between two objects' feet: kept
      continue;
    }
    points_[position_[i]].ground = 0;
    ++i;
  }
}

// Whether return i carries the road the vehicle stands on: its column's first return, level
// with the start (vehicle_ground), or the road going on from a lower ring's return there that
// does not stand out (road_beyond); in either case within level_m in height of it.
bool ColumnProfiles::carries_vehicle_road(const Cloud& cloud, Index i, float level_m) const {
  if (first_in_column(cloud, i)) {
    return points_[position_[i]].vehicle_ground != 0 && std::abs(cloud.z[i] - start_z_) <= level_m;
  }
  return goes_on_from_road(cloud, i, level_m, std::numeric_limits<float>::max());
}

// Whether return i is the road going on from a lower ring's return in its column that does
// not stand out (road_beyond), within level_m in height of it and reach_m in range.
bool ColumnProfiles::goes_on_from_road(const Cloud& cloud, Index i, float level_m,
                                       float reach_m) const {
  const Index k = position_[i];
  for (Index j = column_start_[cloud.column[i]]; j < k; ++j) {
    const Index lower = points_[j].index;
    if (points_[j].road_beyond == i && stands_out_[lower] == 0 &&
        std::abs(cloud.z[i] - cloud.z[lower]) <= level_m &&
        cloud.range_xy[i] - cloud.range_xy[lower] <= reach_m) {
      return true;
    }
  }
  return false;
}

// Whether the run is an object joined to the road behind it, whose returns [keep_a, keep_b]
// are then that road. The road lies at one end of the run, taken by the walk, carrying the
// vehicle's road (carries_vehicle_road) over road_anchor(); the ring steps back onto it from
// the object's edge (steps_behind); the object's part holds a return the walk refused (its
// foot, level with the road, may have been taken where the rings over it did not return),
// or the road part lies level with the road it carries (whole_run_level_m).
// embankment_s1502 at 5 Hz: ring 1 along a car's foot, then 1.7 m of the road's edge, past
// which it meets the fields 2.9 m lower.
bool ColumnProfiles::road_behind_object(const Cloud& cloud, const RingRun& run, Index& keep_a,
                                        Index& keep_b) const {
  Index lead = run.a;  // [run.a, lead): the leading part the walk took
  while (lead <= run.b && taken(lead)) ++lead;
  // The walk took the whole run (the object's foot too low for it, a car's sill 0.05-0.1 m
  // over the road, embankment_s1502 at 20 Hz): an edge anywhere, and the road part level
  // with the road it carries within whole_run_level_m, not the walk's 0.15 m (a low
  // fence's line 19 m out goes on from the road by that: fences_s1502 at 5 Hz).
  const bool whole = lead > run.b;
  const float level_m = whole ? p_.whole_run_level_m : std::numeric_limits<float>::max();
  // Whether the returns [from, to] carry the vehicle's road over road_anchor().
  const auto carries_road = [&](Index from, Index to) {
    Index first = kNone, last = kNone;
    for (Index i = from; i <= to; ++i) {
      if (!carries_vehicle_road(cloud, i, level_m)) continue;
      if (first == kNone) first = i;
      last = i;
    }
    return first != kNone && apart(cloud, first, last, road_anchor(cloud.range_xy[first]));
  };
  Index trail = run.b;  // (trail, run.b]: the trailing part the walk took
  if (whole) {
    lead = run.b;
    trail = run.a;
  } else {
    while (taken(trail)) --trail;
  }
  // The road before the object: the edge nearest the refused returns.
  for (Index e = lead; e > run.a + 1; --e) {
    if (!steps_behind(cloud, e, e - 1, e - 2)) continue;
    if (carries_road(run.a, e - 1)) {
      keep_a = run.a, keep_b = e - 1;
      return true;
    }
    break;
  }
  // The road after it.
  for (Index e = trail; e + 1 < run.b; ++e) {
    if (!steps_behind(cloud, e, e + 1, e + 2)) continue;
    if (carries_road(e + 1, run.b)) {
      keep_a = e + 1, keep_b = run.b;
      return true;
    }
    break;
  }
  return false;
}

// How far along the ring the road behind an object must carry the vehicle's road, at
// `range_m`: road_behind_min_rad of the ring, at least road_behind_min_m and at most
// shadow_anchor_m. Close to the vehicle a levee's edge leaves 0.4-0.6 m of road past a
// car's corner (embankment_s2604, embankment_s2303 tilted); 17-19 m out a low fence's foot
// runs level with the road over as much (fences_s1802 at 5 Hz) and needs the whole anchor.
float ColumnProfiles::road_anchor(float range_m) const {
  return std::min(p_.shadow_anchor_m,
                  std::max(p_.road_behind_min_m, p_.road_behind_min_rad * range_m));
}

// Whether the ring steps from return `near` back to `far` past an object's edge and goes on
// from `far` to `next` as the surface behind it: farther by more than edge_step_ratio times
// the distance across the ray between them (the surface joining them would lie within 18
// degrees of the rays) and by more than edge_step_min_m (over the range noise between
// columns a few centimetres apart: an oblique wall's foot, embankment_s2005 at 5 Hz, 0.07 m
// farther over 0.02 m across; a low fence's oblique foot 18 m out at 5 Hz, fences_s1702,
// 0.10-0.12 m over 0.03 m), then on to `next` by less than half that step (a surface
// running along the rays steps on alike: a car's side seen end-on, hills_s3101). A car's
// foot ending just short of the ring's road steps back by little (0.13-0.14 m:
// embankment_s2205 dual and tilted); a car's foot stepping in and out along the ring steps
// back 0.12 m over 0.03 m across, 3.9 times (embankment_s2905 frame 1).
bool ColumnProfiles::steps_behind(const Cloud& cloud, Index near, Index far, Index next) const {
  const float step = cloud.range_xy[far] - cloud.range_xy[near];
  return steps_back(cloud, near, far) &&
         std::abs(cloud.range_xy[next] - cloud.range_xy[far]) < 0.5f * step;
}

// Whether the ring steps from return `near` back to `far` past an object's edge: farther by
// more than edge_step_ratio times the distance across the ray between them and by more
// than edge_step_min_m (steps_behind).
bool ColumnProfiles::steps_back(const Cloud& cloud, Index near, Index far) const {
  const float step = cloud.range_xy[far] - cloud.range_xy[near];
  if (!(step > p_.edge_step_min_m)) return false;  // the cheap test first
  return step > p_.edge_step_ratio * distance_across_rays(cloud, near, far);
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
// to returns behind it (across the frame's edge, only an object's face's end: end_open).
bool ColumnProfiles::stands_out(const Cloud& cloud, Index first, Index last, Index a,
                                Index b) const {
  const float extent = std::hypot(cloud.x[b] - cloud.x[a], cloud.y[b] - cloud.y[a]);
  if (extent > p_.silhouette_max_m) return wide_silhouette(cloud, first, last, a, b, extent);
  if (a < b && !turns_under_half(cloud, a, b)) return false;
  // At one range (a face) asked only across the frame's edge: the walk along the run costs.
  const auto face = [&] { return a < b && at_one_range(cloud, a, b); };
  const RingBeyond before = beyond_end(cloud, first, last, a, false);
  const bool open_a = end_open(cloud, a, before, before.across && face());
  if (!open_a && !before.across) return false;
  const RingBeyond after = beyond_end(cloud, first, last, b, true);
  if (!open_a) return falls_across_edge(cloud, a, before, after) && face();
  return end_open(cloud, b, after, after.across && face()) ||
         (falls_across_edge(cloud, b, after, before) && face());
}

// Whether run end `end`, at the frame's edge, opens across it all the same where the run
// lies at one range (the caller asks): the ring's return across the edge (`across`) is
// farther by the motion slack and lower, and past the run's other end (`other`) the ring
// meets nothing over at least twice sky_columns. A falling ring meeting the sky over a
// stretch on one side and farther, lower returns on the other has the terrain out of its
// reach on both; the face between is an object met straight ahead past a grade change,
// level with the road or not (slope_s6701 at 20 Hz: ring 6 on an object 34.3 m out, 0.95 m
// over the slope falling away and level with the vehicle's ground, the sky over 32 columns
// on one side, an object 41 m out and 0.36 m lower across the edge; end_open asks for a
// face under the ring below's ground). A crest's top met straight ahead with the ring going
// on to farther terrain past its other end, without the sky between, stays ground. Only
// in a whole rotation (kMinRotationColumns): the ends of a capture's last fragment are no
// neighbours (slope_s5601 at 20 Hz, 36 columns: ring 4's road at its last two columns).
bool ColumnProfiles::falls_across_edge(const Cloud& cloud, Index end, const RingBeyond& across,
                                       const RingBeyond& other) const {
  return across.across && frame_columns() >= kMinRotationColumns &&
         other.gap >= 2 * p_.sky_columns &&
         farther(cloud.range_xy[end], cloud.range_xy[across.index], true) &&
         cloud.z[across.index] < cloud.z[end];
}

// Run [a, b] of one ring, longer than silhouette_max_m: a wider silhouette
// (wide_silhouette_max_m, within wide_silhouette_range_m) over the sensor with the sky at
// both ends, each end far past its column's ground return of the ring below. The ground
// between is unseen, and terrain rising to meet the ray there would meet it along more of
// the ring than an object's width: bank_s5901, the top of an object 6.1 m wide 38-42 m
// out, 1.6 m over a bank's top that the ring below met 19 m out. Nearer, a ring over the
// sensor meets a bank's face or a hill's top against the sky a few metres past the ring
// below (bank_s5905 at Hi-Res, ring 15 at 16 m; hills_s5002 tilted, ring 12 at 33 m);
// farther, the outline of hills 80-90 m out (hills_s104 at 5 Hz, bank_s804).
bool ColumnProfiles::wide_silhouette(const Cloud& cloud, Index first, Index last, Index a, Index b,
                                     float extent) const {
  if (extent > p_.wide_silhouette_max_m || p_.sensor_z <= 0.f) return false;
  for (const Index end : {a, b}) {
    if (cloud.z[end] <= p_.sensor_z || cloud.range_xy[end] > p_.wide_silhouette_range_m ||
        !far_past_lower_ground(cloud, end)) {
      return false;
    }
  }
  return beyond_end(cloud, first, last, a, false).gap >= p_.sky_columns &&
         beyond_end(cloud, first, last, b, true).gap >= p_.sky_columns;
}

// Whether return `end` lies more than wide_silhouette_past_lower times as far out as its
// column's return of the ring below, taken as ground.
bool ColumnProfiles::far_past_lower_ground(const Cloud& cloud, Index end) const {
  const Index j = lower_ring_ground(cloud, end);
  return j != kNone && points_[j].r * p_.wide_silhouette_past_lower < points_[position_[end]].r;
}

// The column point of return `end`'s column's return of the ring below where that is
// ground, else kNone.
std::size_t ColumnProfiles::lower_ring_ground(const Cloud& cloud, Index end) const {
  const Index j = lower_ring_return(column_start_[cloud.column[end]], position_[end]);
  return j != kNone && points_[j].ground != 0 ? j : kNone;
}

// The ring's return beyond run end `end` (positions first..last): the next one (`after`)
// or the one before, with the columns without a return between them; at the frame's edge,
// the ring's return across it (its first or last one, across_edge) where the frame is a
// whole rotation there, else none, the gap up to the edge, beyond which nothing is known.
ColumnProfiles::RingBeyond ColumnProfiles::beyond_end(const Cloud& cloud, Index first, Index last,
                                                      Index end, bool after) const {
  const int column = cloud.column[end];
  if (after ? end + 1 < last : end > first) {
    const Index beyond = after ? end + 1 : end - 1;
    return {beyond, columns_between(cloud, end, beyond)};
  }
  int around = 0;
  const Index across = across_edge(cloud, first, last, end, after, around);
  if (across == kNone) return {kNone, after ? frame_columns() - 1 - column : column};
  return {across, around, true};
}

// The ring's return across the frame's edge from its return `end` at the edge (its first
// one when `after`, else its last), where the frame is a whole rotation there (the two
// returns' azimuths as close as their column gap says), else kNone. `around` is set to the
// columns without a return between them.
std::size_t ColumnProfiles::across_edge(const Cloud& cloud, Index first, Index last, Index end,
                                        bool after, int& around) const {
  const int columns = frame_columns();
  const int column = cloud.column[end];
  const Index across = after ? first : last - 1;
  if (across == end) return kNone;
  around =
      (after ? cloud.column[across] + columns - column : column + columns - cloud.column[across]) -
      1;
  const float ex = cloud.x[end] - p_.sensor_x, ey = cloud.y[end] - p_.sensor_y;
  const float ox = cloud.x[across] - p_.sensor_x, oy = cloud.y[across] - p_.sensor_y;
  const float cos_apart = (ex * ox + ey * oy) / (std::hypot(ex, ey) * std::hypot(ox, oy));
  const float step_rad = 2.f * std::numbers::pi_v<float> / static_cast<float>(columns);
  if (cos_apart >= std::cos(kAzimuthSlack * static_cast<float>(around + 1) * step_rad))
    return across;
  return kNone;
}

// Whether a run's end return `end` opens onto the sky (`gap` columns without a return to
// the ring's next return, or to the frame's edge where none is known, reach sky_columns)
// or onto a return behind it (farther away) on the same side of the frame's edge.
// Across the edge, where the vehicle moved between the two, a return farther by the motion
// slack opens only the end of an object's face (`face`: a run at one range) seen past a
// drop (under_lower_ground): a box on a slope falling away past a grade change, straight
// ahead where frames are cut (slope_s4405 at 20 Hz: 32.6 m out, 1 m under the road's last
// ring, the ring passing on to 48 m across the edge). For any run it cost hills and garage
// F1 (up to -0.0048, hills_s2305 at Hi-Res; a crest's top met by one ring straight ahead,
// hills_s2803); for any run past a drop, a valley's floor met sideways (hills_s1805 at
// 20 Hz); for any run at one range, garage F1 (up to -0.0023).
bool ColumnProfiles::end_open(const Cloud& cloud, Index end, const RingBeyond& beyond,
                              bool face) const {
  if (beyond.gap >= p_.sky_columns) return true;  // no return for a while: the sky
  if (beyond.index == kNone) return false;
  if (beyond.across) {
    return face && farther(cloud.range_xy[end], cloud.range_xy[beyond.index], true) &&
           under_lower_ground(cloud, end);
  }
  return farther(cloud.range_xy[end], cloud.range_xy[beyond.index]) ||
         stopped_by_face(cloud, end, beyond.index);
}

// Whether return `end` lies more than drop_m under its column's return of the ring below,
// taken as ground: the walk met it as a lower surface past a grade change.
bool ColumnProfiles::under_lower_ground(const Cloud& cloud, Index end) const {
  const Index j = lower_ring_ground(cloud, end);
  return j != kNone && points_[j].z - points_[position_[end]].z > p_.drop_m;
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

}  // namespace vlpground::detail
