// Level 3's walk (docs/detector.md, "Column profiles", rules 1-3 and 6): each column outwards
// ring by ring from the ground under the vehicle, a return continuing the column's ground
// profile when the surface from the last ground return to it is a plausible continuation.
#include <algorithm>
#include <cmath>

#include "column_profile.hpp"

namespace vlpground::detail {

using Index = std::size_t;

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
  const Index j = next_advancing(k, end);
  if (j == end) return false;
  const ColumnPoint& next = points_[j];
  const float gradient = gradient_between(points_[k], next);
  if (next.steep != 0 || std::abs(gradient) > p_.max_gradient) return false;
  return bend > 0.f ? gradient >= step : gradient <= step;
}

// Whether return k, reached from the last ground return at gradient `step`, lies on the
// level-2 surface where that surface has ground of its own, and the column's next return
// (at least resume_on_level2_min_m farther) runs on from it on that surface, not steep, at
// `step` within resume_gradient_change: terrain that bent to the chord's gradient and
// holds it, as the cells measured it. The street seen over a garage ramp's retaining wall
// from inside the ramp, rising 0.07-0.1 on a tilted mount (garage_s5405_tilt); not a
// fence's top that level 2 was fitted to, seen by two rings 0.8 m apart (fences_s4805_dual).
bool ColumnProfiles::runs_on_measured_level2(Index k, Index end, float step) const {
  const ColumnPoint& q = points_[k];
  if (!on_measured_level2(q)) return false;
  const Index j = next_advancing(k, end);
  if (j == end) return false;
  const ColumnPoint& next = points_[j];
  const float gradient = gradient_between(q, next);
  return next.r - q.r >= p_.resume_on_level2_min_m && next.steep == 0 &&
         std::abs(gradient - step) <= p_.resume_gradient_change && on_measured_level2(next);
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
// ground of its own (unless, on the first try, the column's next two returns run on from k
// in one straight line: runs_on_in_line). The street seen over a retaining wall from deep
// in a ramp, its near part lower than the sensor (garage), where level 2 follows the ramp
// and has no ground of its own; not a car's roof seen over a van's side on a measured road,
// with a truck's box or a facade's upper floors beyond it (jam).
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
  if (stands_over_measured_level2(k) && !(level_run_top == kNoLevelRun && runs_on_in_line(k, end)))
    return false;
  const bool under_face_top = points_[k].z < level_run_top;
  Index from = k;
  Index j = next_advancing(k, end);
  if (j == end) return false;
  for (;;) {
    const ColumnPoint &q = points_[from], &on = points_[j];
    const float gradient = gradient_between(q, on);
    if (on.steep != 0 || gradient < 0.f || gradient >= p_.shoulder_gradient) return false;
    for (Index m = j + 1; m < end; ++m)
      if (under_overhang(on, points_[m])) return false;
    const Index beyond = next_advancing(j, end);
    if (beyond != end) {
      const float bend = gradient_between(on, points_[beyond]) - gradient;
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

// Whether the column's next two returns beyond return k (points [k + 1, end)), neither
// steep, go on from k in one straight line: the gradient from k to the next and from there
// to the one after differ by at most in_line_gradient_change, the last at least
// in_line_span_m beyond k. Three returns in one line over 10 m or more are one surface:
// the street seen over a garage ramp's retaining wall from inside the ramp, 1.6 m over the
// level-2 surface that follows the ramp's ground (garage_s501_hires frame 4, column 262:
// 17.8, 25.5 and 45.2 m out, rising 0.066 and 0.065 on the pitched vehicle).
// rises_on_over_sensor asks it only on the walk's first try: taken as level ground running
// on under a face's top, obstacle returns past a car's side lay in line by chance (jam_s604
// frame 0, column 471: 18.4, 27 and 51 m out, 0.97, 1.46 and 2.82 m up, 0.0003 apart).
bool ColumnProfiles::runs_on_in_line(Index k, Index end) const {
  const Index j = next_advancing(k, end);
  if (j == end) return false;
  const Index b = next_advancing(j, end);
  if (b == end) return false;
  const ColumnPoint &q = points_[k], &next = points_[j], &last = points_[b];
  if (next.steep != 0 || last.steep != 0 || last.r - q.r < p_.in_line_span_m) return false;
  return std::abs(gradient_between(next, last) - gradient_between(q, next)) <=
         p_.in_line_gradient_change;
}

// The column's first return after k at least min_advance_m farther than k (end: none).
Index ColumnProfiles::next_advancing(Index k, Index end) const {
  for (Index j = k + 1; j < end; ++j)
    if (points_[j].r >= points_[k].r + p_.min_advance_m) return j;
  return end;
}

// Whether return k, rising from the column's last ground return at gradient `step` by more
// than the profile may bend up at one return, is the terrain climbing on: it lies over the
// sensor (met by a rising ray) or under the ground the vehicle stands on, on the level-2
// surface where that surface has ground of its own (on_measured_level2), and the column's
// next return goes on from it on that surface, not steep, bending down by no more than
// gradient_step. A valley's far side behind a convex shoulder, the column's rise there too
// sudden for the walk (hills_s702, hills_s402), or rising back from a valley's floor 2.3 m
// under the vehicle (hills_s1903: 0.43 m up over the 4 m from ring 3 to ring 4, where the
// walk allows 0.73 m less the descent extrapolated); not a fence line's top or a face that
// level 2 was fitted to, over the vehicle's ground and under the sensor (fences_s2603: a
// face 21-23 m out, 0.7-1.4 m up), nor one past which the next ring falls to the ground
// beyond. Between the vehicle's ground and the sensor only the column's first return
// (nothing walked before it), with first_climb_returns returns going on from it so: a
// hillside rising from beside the vehicle, which a Puck Hi-Res's lowest ring (-10 degrees)
// meets 5.6 m out and 1 m up, 0.06 m over the start's allowance, its rings 1-15 climbing on
// at 0.4-0.5 on level 2 (hills_s4103_hires: 10082 ground returns lost, F1 0.8895).
bool ColumnProfiles::climbs_on_level2(Index k, Index end, float step) const {
  const ColumnPoint& q = points_[k];
  const bool between = q.z <= p_.sensor_z && q.z >= start_z_;
  if (p_.sensor_z <= 0.f || (between && profile_size_ != 1) || !on_measured_level2(q)) {
    return false;
  }
  const int going_on = between ? p_.first_climb_returns : 1;
  Index from = k;
  for (int n = 0; n < going_on; ++n) {
    const Index j = next_advancing(from, end);
    if (j == end) return false;
    const ColumnPoint &a = points_[from], &next = points_[j];
    const float gradient = gradient_between(a, next);
    if (next.steep != 0 || gradient > p_.max_gradient || gradient < step - p_.gradient_step ||
        !on_measured_level2(next)) {
      return false;
    }
    from = j;
  }
  return true;
}

// Whether return k, over the walk's rise allowance from the descending profile extrapolated
// under it but within it from the last ground return's own level (`within_rise`; only a
// descent tells them apart), is a valley's far side rising past a floor that lies between
// the two rings: the column's next return goes on rising at least as steeply as the chord
// to k (bends_on, `step` from the last ground return). Sim hills_s605 frame 2, column 941:
// the column falls at 0.105-0.126 to ring 3, 24 m out and 1.9 m down; ring 4, 3.2 m
// farther, stands 0.46 m over ring 3 but 0.86 m over the descent extrapolated (0.64 m
// allowed); ring 5 rises on at 0.18. Off with valley_far_side.
bool ColumnProfiles::rises_past_valley_floor(Index k, Index end, float gradient, float step,
                                             bool within_rise) const {
  return p_.valley_far_side && within_rise && bends_on(k, end, step, step - gradient);
}

// Whether return k, rising from the column's last ground return (last_r, last_z) by more
// than the profile may bend up at one return, is the terrain steepening over the sensor
// where level 2 lags: the walk has followed the column over ground returns of its own (not
// only the start's guess), the chord to k bends the profile's gradient up by no more than
// gradient_step (`bend`), k lies over the sensor on a surface rising more steeply than its
// ray, as do the column's next rising_ray_returns returns (rises_over_its_ray: a roof or a
// canopy is met from below), and k lies at most single_rise_m over the chord from the last
// ground return to the next of them (terrain bending up lies on or under that chord; a bush
// on a bowl's far side stands over it, bowl_s1401 at 5 Hz). A hillside steepening from
// 0.11 to 0.36 past a ring over the sensor, each higher ring meeting it farther and higher
// (hills_s2301: rings 10-12 at 30, 37 and 47 m, 2.6-7.5 m over the sensor).
bool ColumnProfiles::steepens_over_its_ray(Index k, Index end, float last_r, float last_z,
                                           float bend) const {
  if (profile_size_ <= 2 || bend > p_.gradient_step || !rises_over_its_ray(k, end, false)) {
    return false;
  }
  // rises_over_its_ray saw the next advancing return: it exists.
  const ColumnPoint &q = points_[k], &next = points_[next_advancing(k, end)];
  return height_over_chord(last_r, last_z, next.r, next.z, q.r, q.z) <= p_.single_rise_m;
}

// Whether q lies within plane_band_m of the level-2 surface where that surface has ground of
// its own (Level2Coverage::measured).
bool ColumnProfiles::on_measured_level2(const ColumnPoint& q) const {
  return std::abs(q.level2_h) <= p_.plane_band_m && level2_.measured(q.index);
}

// Whether the column's next lower ring met the face that steep return k lies on, lower
// down: more than face_below_m under k and steeply under it (the segment between them rises
// more than 45 degrees, the steep test). A face's foot is its lowest point; where the face
// goes on under a return, that return is no foot, level with the profile or not (a tree
// trunk in a dip past a crest, whose lower ring met it 1.3 m lower: hills_s1005). The lower
// return may be ground itself: then it is the foot, the face rising from it.
bool ColumnProfiles::face_goes_on_below(Index begin, Index k) const {
  const Index j = lower_ring_return(begin, k);
  if (j == kNone) return false;
  const ColumnPoint &q = points_[k], &below = points_[j];
  const float drop = q.z - below.z;
  return drop > p_.face_below_m && std::abs(q.r - below.r) < drop;
}

// Whether return `over` (the next of q's column) rises over q steeper than any ground
// (max_gradient): a face or a crown over it, not a hillside rising on (hills_s903 dual:
// ring 11 rising at 0.3 from ring 10's return 30 m out, over a dip the rings do not see).
bool ColumnProfiles::face_over(const ColumnPoint& q, const ColumnPoint& over) const {
  return over.z - q.z > p_.max_gradient * std::max(0.f, over.r - q.r);
}

// Whether `above`, the column's next return (a higher ring), lies more than overhang_m
// nearer than q and over q's ray at its distance.
bool ColumnProfiles::under_overhang(const ColumnPoint& q, const ColumnPoint& above) const {
  if (above.ring == q.ring || above.r >= q.r - p_.overhang_m) return false;
  const float ray_z = p_.sensor_z + (q.z - p_.sensor_z) * (above.r / q.r);
  return above.z > ray_z;
}

// Whether a later return j of the column than k (a higher ring) overhangs k (under_overhang)
// level with it within level_m, and also(j) holds: k met the far edge of something the rings
// over it met from below.
template <class Also>
bool ColumnProfiles::level_overhang(Index k, Index end, float level_m, Also also) const {
  const ColumnPoint& q = points_[k];
  for (Index j = k + 1; j < end; ++j) {
    const ColumnPoint& above = points_[j];
    if (std::abs(above.z - q.z) < level_m && under_overhang(q, above) && also(j)) return true;
  }
  return false;
}

// Whether a later return of the column than k (a higher ring) lies more than overhang_m
// nearer, over k's ray there and level with k (within single_rise_m): k met the far edge of
// a roof or a canopy that the rings over it met from below (a carport on a bank's top).
bool ColumnProfiles::under_level_overhang(Index k, Index end) const {
  return level_overhang(k, end, p_.single_rise_m, [](Index) { return true; });
}

// Whether return k, over the sensor, met the far edge of an underside that a later return of
// the column (a higher ring) met from below, nearer by overhang_m to underside_reach_m and
// level with k within underside_level_m. That return is on an underside, not a face, where
// no lower ring met its distance (within underside_face_m) under it: a face's side met by a
// higher ring level with ground past it lies over the lower rings' returns on that face.
bool ColumnProfiles::meets_underside_edge(Index begin, Index k, Index end) const {
  const ColumnPoint& q = points_[k];
  return q.z > p_.sensor_z && level_overhang(k, end, p_.underside_level_m, [&](Index j) {
           return q.r - points_[j].r <= p_.underside_reach_m && !face_under(begin, j);
         });
}

// Whether a lower ring than return j's met a face under j: a return within underside_face_m
// of j's distance and lower.
bool ColumnProfiles::face_under(Index begin, Index j) const {
  const ColumnPoint& top = points_[j];
  for (Index i = begin; i < j; ++i) {
    const ColumnPoint& w = points_[i];
    if (w.ring < top.ring && std::abs(w.r - top.r) < p_.underside_face_m && w.z < top.z) {
      return true;
    }
  }
  return false;
}

// Whether the kink before return k (a return more than drop_m under the profile that kink
// extrapolated) was an object rather than a bend of the terrain. Only with ground of the
// column before the kink to go back to (not only the start's guess: the street over a ramp's
// parapet, garage_s2); the walk asks only for a kink that rose from that ground
// (`last_kinked` in walk_column). Either k stands more than single_rise_m over a level-2
// surface with ground of its own there, so it is on no lower surface either (a second fence
// line past the first, fences_s102), or k lies on such a surface and on the ground before
// the kink extrapolated, nearer to it than to the kink's height: that ground ran on under
// the kink, which stood on it (a mesh fence's low wires or a fence line 0.15-0.4 m up, the
// next ring passing over it onto the field behind, fences_s203_tilt). A kerb's pavement
// stays level with its kink (urban_s4_hires), as a plateau does.
bool ColumnProfiles::kink_was_an_object(Index k, const BeforeKink& before, float kink_z) const {
  if (before.profile_size <= 1) return false;
  const ColumnPoint& q = points_[k];
  if (stands_over_measured_level2(k)) return true;
  const float off_ground = q.z - (before.last_z + before.gradient * (q.r - before.last_r));
  return std::abs(off_ground) <= p_.single_rise_m &&
         std::abs(off_ground) < std::abs(q.z - kink_z) && on_measured_level2(q);
}

// One column outwards from the sensor. The profile is the last ground return (r, z) and
// the gradient dz/dr along the column, starting at the ground under the sensor. Heights over
// the profile go to `height` (by cloud point).
void ColumnProfiles::walk_column(Index column, Index begin, Index end,
                                 const std::vector<float>& plane_height,
                                 std::vector<float>& height) {
  if (begin == end) return;
  // The profile starts level under the sensor: at z = 0 when the mounting height is known
  // (the vehicle frame's ground), else on the vehicle's surface. Starting with that
  // surface's gradient was worse on hills (a local tilt extrapolated 10 m).
  float last_r = 0.f;
  float last_z = start_z_;
  float gradient = 0.f;
  float gradient_r = 0.f;      // where the gradient holds (the start: level under the vehicle)
  bool blocked = false;        // an obstacle return since the last ground return
  bool obstacle_seen = false;  // an obstacle return since the start
  bool faces_only = true;      // every obstacle return since the last ground return was steep
  // The last steep obstacle return (r < 0: none since the last ground return): a return on
  // the top of its wall still counts as that face.
  float face_r = -1.f, face_z = 0.f;
  int last_ring = -1;  // ring of the last ground return (-1: the start)
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
           std::abs(bend) <=
               p_.resume_gradient_change + p_.resume_curvature_per_m * std::max(0.f, drift) &&
           ((std::abs(points_[k].level2_h) <= p_.single_rise_m && bends_on(k, end, step, bend)) ||
            runs_on_measured_level2(k, end, step) ||
            rises_over_its_ray(k, end, faces_only, level_run_top));
  };
  profile_size_ = 0;
  add_to_profile(last_r, last_z);
  Index last_ground = end;  // the column's last ground return taken (end: none yet)
  // The walk's state before the last ground return, kept while that return is a kink
  // (kink_was_an_object may take it back); the kink itself is then last_ground.
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
      // met a wall over the ground it hides, the plane passing there by chance, garage_s105;
      // within first_foot_over_m over the start it may be, a building's foot on a pavement)
      // Nor where the climb is only a guess (a shed's wall on a bank top the rings never
      // see, where the bank's slope extrapolated runs into it; a facade far past a gentle
      // rise onto a fence's foot).
      const bool climb_guessed = foot_climb_is_guess(gradient, advance);
      const bool first_over_start = profile_size_ == 1 && k == begin && over > 0.f;
      const bool start_guessed = profile_size_ == 1 && !first_over_start;
      const float foot_m = first_over_start ? p_.first_foot_over_m : p_.plane_foot_m;
      // (the column's first return, on the level-2 surface, a little further under the
      // start's level guess: first_foot_under_m)
      const float under_m = k == begin && std::abs(q.level2_h) < p_.steep_band_m
                                ? p_.first_foot_under_m
                                : p_.steep_band_m;
      q.ground = (over < p_.steep_band_m && over > -under_m && !guess_off && !climb_guessed) ||
                 (std::abs(plane_height[q.index]) < p_.steep_band_m &&
                  (std::abs(over) < foot_m || start_guessed));
      if (q.ground != 0 && face_goes_on_below(begin, k)) q.ground = 0;
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
    if (last_kinked && over < -p_.drop_m && kink_was_an_object(k, before_kink, last_z)) {
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
      // a top the rings cannot see (past_hidden_top), still rising as a shoulder or rising
      // gently where the climb levelled off (climb_levelled_off), unless it lies on the
      // level-2 surface where that surface has ground of its own (the climb's hillside rising
      // on, met by the next ring far out: hills_s504, hills_s702).
      // With the next return rising over it steeper than any ground (a face or a crown over
      // it, not a hillside rising on), it is judged with its ring (drop_covered_tops).
      const bool last = k + 1 == end;
      if ((rising || climb_levelled_off(gradient, step)) && past_hidden_top(r, last_r, last_z) &&
          (last || face_over(q, points_[k + 1])) && !on_measured_level2(q)) {
        accept = accept && !last;
        hidden_tops_.push_back(std::uint64_t{q.index} << 1 | (last ? 0u : 1u));
      }
    } else {
      const float rise = blocked              ? p_.blocked_rise_m + p_.blocked_rise_per_m * advance
                         : profile_size_ == 1 ? p_.start_rise_m + p_.start_rise_per_m * advance
                                              : p_.rise_m + p_.rise_per_m * advance;
      // Past an obstacle the ground may have risen out of sight: a gentle slope from the
      // last ground return is taken (a car roof is a steep step from it).
      // Before any ground return of the column the profile's gradient is only the start's
      // guess: resuming on it needs the level-2 surface not to disagree (a car roof seen
      // past a car side next to the sensor, in a jam), or ground rising over the sensor.
      // (the tests in order of cost, each asked only where the ones before leave it open)
      const auto takes = [&](float level_run_top) {
        if (!(std::abs(step) <= p_.max_gradient)) return false;
        if (over <= rise) return true;
        if (!blocked) {
          return climbs_on_level2(k, end, step) ||
                 steepens_over_its_ray(k, end, last_r, last_z, step - gradient) ||
                 rises_past_valley_floor(k, end, gradient, step, z - last_z <= rise);
        }
        if (!(std::abs(step - gradient) <= p_.resume_gradient_change))
          return resumes_bent(k, step, 0.5f * (last_r + r) - gradient_r, level_run_top);
        return profile_size_ > 1 || !(std::abs(q.level2_h) > p_.single_rise_m) ||
               rises_over_its_ray(k, end, faces_only, level_run_top);
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
      // Past an obstacle, not the far edge of an underside over the sensor: a crown or a
      // roof met from below by the rings over it.
      if (accept && blocked && meets_underside_edge(begin, k, end)) accept = false;
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
      q.shadowed =
          refused_here && blocked && std::abs(step) <= p_.max_gradient && !under_a_ray(r, z, q.ring)
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
    // Only a kink that rose from the ground before it, by keep_gradient_rise per metre or
    // more, may be taken back: one level with that ground only ends a descent the profile's
    // gradient carried on (the road behind a box on an embankment, after the box's low
    // return taken as the column's first ground and the road 0.34 m under it:
    // embankment_s4804_dual).
    last_kinked = q.kinked != 0 && step >= p_.keep_gradient_rise;
    if (last_kinked) {
      before_kink = {last_r, last_z, gradient, gradient_r, last_ring, profile_size_, last_ground};
    }
    q.resumed = blocked;
    // Ground level with the ground under the vehicle, no obstacle before it in the column:
    // that ground going on (rule 4 keeps it, whatever the level-2 surface says, when no
    // ground is left before it: a bush in front taken by the walk, then as a silhouette).
    q.vehicle_ground = !obstacle_seen && std::abs(z - start_z_) <= 0.5f * p_.single_rise_m;
    // A ground return level with the start, no obstacle before it, and this one level with
    // it (a higher ring, nothing between): the vehicle's road going on, seen by two rings.
    if (last_ground != end && !blocked && points_[last_ground].vehicle_ground != 0 &&
        q.ring > points_[last_ground].ring && std::abs(z - last_z) <= 0.5f * p_.single_rise_m) {
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

// Whether a return rising by `step` from the last ground return, less than a shoulder, lies
// where a climb at `gradient` levelled off: the gradient falls by more than hidden_top_bend
// to it. A hillside rising on less steeply bends gently (hills_s605: 0.11 to 0.07); a bank's
// face tops out (bank_s2804: 0.45 to 0.07), and what the next ring meets far out, rising
// gently over it, stands on the top (past_hidden_top).
inline bool ColumnProfiles::climb_levelled_off(float gradient, float step) const {
  return step > 0.f && gradient - step > p_.hidden_top_bend;
}

// Whether the profile, extrapolated `advance` past its last ground return with `gradient`,
// climbs more than steep_climb_m there: far past the last ground return on a climbing
// profile the extrapolation is only a guess.
inline bool ColumnProfiles::climb_is_guess(float gradient, float advance) const {
  return gradient * advance > p_.steep_climb_m;
}

// Whether a steep return (a wall's foot), `advance` past the last ground return, stands on a
// climb that is only a guess: one over steep_climb_m, or, where the profile climbs gently,
// one over gentle_steep_climb_m. A bank's face is measured ring after ring at its gradient;
// a gentle gradient may come from one raised return (the foot of a fence, 0.16 m up 21 m
// out) and, carried 9 m on to a facade, it lifts the profile onto the facade's foot.
inline bool ColumnProfiles::foot_climb_is_guess(float gradient, float advance) const {
  return climb_is_guess(gradient, advance) ||
         (gradient < p_.gentle_climb_gradient && gradient * advance > p_.gentle_steep_climb_m);
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

}  // namespace vlpground::detail
