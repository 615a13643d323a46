// Level 3 down the columns (docs/detector.md, "Column profiles", rule 4): ground returns
// raised over the level-2 surface need a raised neighbour; rises refuted by a neighbouring
// column, raised groups and their orphaned feet are dropped.
#include <algorithm>
#include <cmath>

#include "column_profile.hpp"

namespace vlpground::detail {

using Index = std::size_t;

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
//   rings), unless it is a crest's top (crest_top), or
// - it ends the column as an object's top (top_at_column_end).
bool ColumnProfiles::drop_raised_groups(Index begin, Index end) {
  bool dropped_any = false;
  auto raised = [&](Index k) { return raised_over_level2(k, 0.5f * p_.single_rise_m); };
  float before_r = 0.f, before_z = start_z_;  // the ground before the group (or the start)
  bool ground_before = false;
  Index k = begin;
  while (k < end) {
    if (!is_ground_neighbour(k) || !raised(k)) {
      if (is_ground_neighbour(k)) {
        before_r = points_[k].r, before_z = points_[k].z, ground_before = true;
      }
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
      drop = drop && !crest_top(k, last, after, before_r, before_z, !ground_before);
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

// Whether the raised group [first, last], standing out of the ground before it (at before_r,
// before_z: the start, or the column's last ground return, `from_start` telling which) and
// of the ground return `after` it, is a crest the column passes over, not an object on the
// ground: it lies along at least crest_min_m, rising on from its first return as the chord
// from the ground before it rises to that return (within resume_gradient_change), and
// - the ground after it lies more than drop_m under the ground before (the far side falling
//   away): the vehicle just below a hill's top, the lowest rings on the top 0.6-0.8 m up,
//   the next on the far side 56 m out and 2.7 m lower (hills_s2304 at Hi-Res); or
// - it is the column's first ground and the level-2 surface under its first return lies
//   more than drop_m under the ground under the vehicle: the cells carried the vehicle's
//   surface down where the terrain climbs, so they show no level ground an object could
//   stand on. The vehicle in a hollow, a hill's flank rising behind it at 0.1 to 1 m up
//   10 m out (rings 0-4), its far side levelling out near the vehicle's height 30 m out,
//   where the cells lie 1.1-1.6 m under the flank (hills_s2305 at Hi-Res).
// A roof or a box's top is level; an object on level ground has that ground behind it and
// under it (fences_s2 at Hi-Res: a box 0.8-0.95 m tall 7-8 m out, its top rising on the
// chord from the start by chance; fences_s2803 at Hi-Res: a box 0.5-0.7 m tall 8-10 m out,
// the cells on the road under it).
bool ColumnProfiles::crest_top(Index first, Index last, Index after, float before_r, float before_z,
                               bool from_start) const {
  const ColumnPoint &a = points_[first], &b = points_[last];
  if (b.r - a.r < p_.crest_min_m || a.r <= before_r) return false;
  const bool far_side_falls = points_[after].z < before_z - p_.drop_m;
  const bool level2_falls_away = from_start && over_fallen_cells(a);
  if (!far_side_falls && !level2_falls_away) return false;
  const float chord = (a.z - before_z) / (a.r - before_r);
  const float along = gradient_between(a, b);
  return std::abs(along - chord) <= p_.resume_gradient_change;
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
    high = high || stands_over_measured_level2(g);
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
      const ColumnPoint& q = points_[k];
      const float over_chord = both ? height_over_chord(points_[previous].r, points_[previous].z,
                                                        points_[next].r, points_[next].z, q.r, q.z)
                                    : 0.f;
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
      const bool vouches_after =
          points_[k].kinked == 0 || points_[k].rises_on != 0 ||
          (next < end && points_[next].r - points_[k].r <= p_.kink_vouch_span * points_[k].r);
      const bool after =
          !bump && next < end && vouches_after && raised_over_level2(next, 0.5f * p_.single_rise_m);
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
      // Where level 2 only extrapolates, a long ring run is terrain that the cells lag or
      // guess wrong, not an object standing on it: over the sensor, the terrain climbing on;
      // as the column's first return, met by its lowest ring past everything else, the
      // street seen over a ramp's parapet from a vehicle pitched on the ramp, 2.9 m under
      // the ramp's plane and 3.1 m over the level-2 surface extrapolated down the ramp's
      // upper bend (garage_s1505 Hi-Res). An object's top is a short run: a tree top in a
      // valley met by ring 0 over a crest (hills_s1204 Hi-Res).
      const auto terrain_run = [&] {
        return (q.z >= p_.sensor_z || k == begin) && !level2_.measured(q.index) &&
               on_ring_run_of(cloud, q.index, p_.rise_run_min_m);
      };
      // Its column's only ground return, under the vehicle's ground, may be the floor a face
      // farther out stands on (floor_under_face); its first, the terrain climbing from the
      // vehicle over cells that fell away (climbs_over_fallen_cells).
      const bool first = previous == end;
      if (!before && !after && !level && !on_chord && !terrain_run() &&
          !(first && next == end && floor_under_face(k, end)) &&
          !(first && next < end && climbs_over_fallen_cells(k, next))) {
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

// Whether ground return k, its column's only one, lies under the ground under the vehicle
// where the column's next return is on a face farther out, rising from at most drop_m over
// k: the floor that face stands on, seen by the lowest ring between walls. The case: the
// vehicle on the street, a ramp falling ahead into a garage; ring 0 on the garage's floor
// 22.6 m out, 2.1 m under the street and 0.5 m over the level-1 plane that level 2 kept
// there; rings 1-12 on the back wall 28.3 m out, from 2.46 m down (garage_s2205 at Hi-Res).
bool ColumnProfiles::floor_under_face(Index k, Index end) const {
  if (k + 1 >= end || !(points_[k].z < start_z_)) return false;
  const ColumnPoint &q = points_[k], &face = points_[k + 1];
  return face.steep != 0 && face.r > q.r && face.z <= q.z + p_.drop_m;
}

// Whether ground return k, its column's first, taken before any obstacle return was refused
// (not resumed), more than half single_rise_m over the ground under the vehicle, is the
// terrain climbing from the vehicle where the level-2 cells fell away (over_fallen_cells)
// and the column's next ground return (`next`, which must exist) lies higher. As for a group
// (crest_top), the cells then show no level ground an object could stand on. The case:
// hills_s101 at Hi-Res (frame 1, column 1296), ring 0 on a gentle climb 10.1 m out, 0.2 m
// up, ring 1 on it 11.3 m out; the cell under ring 0 (near the vehicle, its own fit failed)
// took a neighbour's surface falling away, 0.68 m under the vehicle's ground there.
bool ColumnProfiles::climbs_over_fallen_cells(Index k, Index next) const {
  const ColumnPoint& q = points_[k];
  if (q.resumed != 0 || !(q.z > start_z_ + 0.5f * p_.single_rise_m)) return false;
  return over_fallen_cells(q) && points_[next].z > q.z;
}

// Whether the level-2 surface under q lies more than drop_m under the ground under the
// vehicle (crest_top, climbs_over_fallen_cells).
bool ColumnProfiles::over_fallen_cells(const ColumnPoint& q) const {
  return q.z - q.level2_h < start_z_ - p_.drop_m;
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
