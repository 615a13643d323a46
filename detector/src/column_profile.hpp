// Third level of the tangent method's terrain model (docs/detector.md, "Column profiles"):
// where the cells of level 2 replace the paper's planes, each column of the range image is
// walked outwards ring by ring from the ground under the vehicle, and a return continues the
// column's ground profile when the surface from the last ground return to it is a plausible
// continuation (gradient, gradient change, no step up); a return on a steep surface, or
// standing over the extrapolated profile, is an obstacle. Terrain of any curvature the rings
// can sample (a bank face, fields below a levee, a ramp) follows; what the column alone
// cannot tell apart (one ring line on a fence or a box between two ground returns) is
// checked against the level-2 surface.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "method.hpp"
#include "terrain_cells.hpp"

namespace vlpground::detail {

/// Height of (r, z) over the chord from (a_r, a_z) to (b_r, b_z) in a column's profile,
/// taken at r clamped to the chord's span (its start where the span is empty).
[[nodiscard]] inline float height_over_chord(float a_r, float a_z, float b_r, float b_z, float r,
                                             float z) {
  const float t = b_r > a_r ? std::clamp((r - a_r) / (b_r - a_r), 0.f, 1.f) : 0.f;
  return z - (a_z + t * (b_z - a_z));
}

struct ProfileParams {
  float sensor_x = 0, sensor_y = 0;
  float sensor_z = 0;  // mounting height (extrinsics z; 0 = unknown)
  HeightPlane vehicle;  // the ground under the sensor (level 2), used when sensor_z is 0
  float max_gradient = 0.62f;   // steepest ground (32 degrees), as the cells
  float gradient_step = 0.3f;   // largest change of the profile's gradient at one return
  // Rise over the extrapolated profile a return may have: rise_m + rise_per_m x distance
  // from the last ground return (the profile may bend up); after an obstacle return in the
  // column only blocked_rise_m + blocked_rise_per_m x distance (no climbing onto a roof).
  float rise_m = 0.25f, rise_per_m = 0.12f;
  float blocked_rise_m = 0.25f, blocked_rise_per_m = 0.03f;
  float resume_gradient_change = 0.06f;  // ... or a return this close to the profile's gradient
  // While that gradient is only the start's guess (fewer than two ground returns of the
  // column: a Puck Hi-Res's lowest ring meets level ground 11 m out, often behind the first
  // obstacle), the terrain may have bent since the point where the gradient holds: by up to
  // this curvature (1/m; a 1 m undulation over a 40 m wavelength) x the distance from that
  // point to the middle of the chord from the last ground return. Taken only where the
  // level-2 surface agrees (within single_rise_m) and the column's next return goes on
  // bending (bends_on), or where it lies on the level-2 surface that has ground of its own
  // and the column's next return, at least resume_on_level2_min_m farther, runs on from it
  // on that surface at the chord's gradient (runs_on_measured_level2: the street seen over a
  // garage ramp's retaining wall, rising 0.07-0.1 on a tilted mount; at 0.3 m, a fence's
  // top 0.66 m up, which level 2 was fitted to and two rings met 0.8 m apart,
  // fences_s4805_dual; at 6 m, garage kept three fifths of the gain).
  float resume_curvature_per_m = 0.025f;
  float resume_on_level2_min_m = 3.f;
  // A rising ray (a return over the sensor) meets ground only where the ground rises more
  // steeply than the ray (a roof or a canopy is met from below, never on top): where the
  // column's next rising_ray_returns returns each rise from the one before at least that
  // steeply, with no steep surface among them, the start's guess may resume there even if
  // the level-2 surface disagrees (the street seen over a ramp's parapet from inside the
  // ramp, where level 2 follows the ramp). One such return is enough where the column ends
  // there and only faces stood in front (rises_over_its_ray).
  int rising_ray_returns = 2;
  // A column's first return between the vehicle's ground and the sensor, over the start's
  // allowance, is the terrain climbing on (climbs_on_level2) only where this many returns
  // go on from it on the measured level-2 surface (a hillside beside the vehicle).
  int first_climb_returns = 2;
  // A return at most this far behind a steep face and not under its last return lies on
  // the wall's top: it counts as that face (on_wall_top).
  float wall_top_m = 0.5f;
  // ... and for the first return of a column, from the ground under the sensor.
  float start_rise_m = 0.25f, start_rise_per_m = 0.12f;
  float drop_m = 0.5f;         // a return this far under the profile starts a lower surface
  // ... level, unless it still rises at least this from the last ground return (and the
  // gradient bends no more than gradient_step): a hill's shoulder keeps that gradient.
  // (Taken as level, a gentler rise lost a valley's far side behind a convex shoulder,
  // hills_s702; keeping any rise at all let a fence line's gentle chord reach a wall's foot.)
  float keep_gradient_rise = 0.05f;
  // Past a descent, a return over the rise allowance from the descent extrapolated but within
  // it from the last ground return's level, the column's next return rising on at least as
  // steeply, is a valley's far side past a floor between two rings (rises_past_valley_floor).
  bool valley_far_side = true;
  // A return rising at least this from the last ground return (a hill's shoulder) is
  // ground only where it is not under an overhang (overhang_m) and not past a hidden top
  // (hidden_top_range_ratio).
  float shoulder_gradient = 0.1f;
  // Level ground seen past a face, under the face's top, may run on under the sensor from
  // return to return rising less than this (rises_on_over_sensor). (At shoulder_gradient,
  // car roofs rising 0.07-0.08 from one to the next past a car's side, jam_s704.)
  float level_run_gradient = 0.06f;
  // ... on a ring run longer than this (drop_short_level_runs). (At silhouette_max_m, the
  // street between cars parked beside a ramp was lost: garage_s604 20 Hz 0.9813 -> 0.9782;
  // roofs past a car's side in a jam ran 0.5-3 m along their ring.)
  float level_run_min_m = 3.f;
  // Past a face, a return under the sensor that stands over a measured level 2 is still
  // taken where the column's next two returns go on from it in one straight line: the
  // gradients from it to the next and from there to the one after differ by at most
  // in_line_gradient_change, over at least in_line_span_m (runs_on_in_line). The street seen
  // over a garage ramp's retaining wall, where level 2 follows the ramp's ground 1.6 m under
  // it (garage_s501_hires). (At 0.008, obstacle returns past a car's side 0.008 apart,
  // jam_s303_5hz: one more high obstacle as ground.)
  float in_line_gradient_change = 0.005f;
  float in_line_span_m = 10.f;
  // Not under an overhang: the column's next (higher) ring met something more than this
  // nearer and over the return's ray there (a tree crown on a bank's top met from below),
  // or a later ring met something that much nearer, over the ray and level with the
  // return, within single_rise_m: a roof or a canopy whose far edge the return met, seen
  // from below by the rings over it (under_level_overhang).
  float overhang_m = 1.f;
  // Not the far edge of an underside: a return over the sensor (met by a rising ray), taken
  // past an obstacle, that a later ring's return overhangs (under_overhang) from at most
  // underside_reach_m nearer, level with it within underside_level_m, with no lower ring's
  // return within underside_face_m of that distance under it (a face met by the rings
  // below, not an underside): a tree crown's underside 2.55 m over a bank's top, met by two
  // rings at a height that the bank's slope extrapolated reaches there (bank_s5603,
  // meets_underside_edge). (Of the tuning captures, level within 0.2 m, 4 lost ground; 0.3 m,
  // 13; with no reach limit, 72: ground level with a canopy over the vehicle 27 m nearer; at
  // 0.3 m with faces counted as undersides, 170: ground seen past a wall's gap; at 0.3 m not
  // only past an obstacle, 121: ground past crowns on a bowl's rising side.)
  float underside_level_m = 0.1f;
  float underside_reach_m = 5.f;
  float underside_face_m = 0.3f;
  // Not past a hidden top: the column's last return, more than this times as far as the
  // ground return before it, where that ground lay over the sensor after a climb
  // (past_hidden_top), unless it lies within plane_band_m of the level-2 surface where that
  // surface has ground of its own (the hillside rising on, met far out: hills_s702). (At
  // 1.6, objects on bank_s1001's top 1.42 times as far were ground; 1.3 cost hills' far
  // sides twice the F1 for no more gain.)
  float hidden_top_range_ratio = 1.4f;
  // ... also where that return rises from the ground return before it less than a shoulder
  // (a lower surface, level from there, for the walk) but the climb's gradient falls by more
  // than this to it: the climb levelled off (climb_levelled_off; a hedge 1.5 m tall on
  // bank_s2804's top 27 m past a face rising at 0.45, met rising 0.07 from the face's last
  // return). (At 0.1, hillsides rising on less steeply past ring 8, with level 2 off them,
  // lost up to 0.0005 F1, hills_s1202_tilt; at 0.3, gradient_step, bank_s2804_strongest
  // kept 77 of its 191 hedge returns as ground.)
  float hidden_top_bend = 0.2f;
  float min_advance_m = 0.3f;    // nearer than this (horizontally) to the last ground return
  float anchor_slack_m = 0.05f;  // ... a ground return moves the profile's end at most
                                 // max_gradient x advance + this up or down
  float steep_band_m = 0.06f;    // a steep return is ground only this close to the profile
  // ... but the column's first return, lying on the level-2 surface (within steep_band_m),
  // down to this under the start's level profile, which is only a guess there: the foot of
  // a low object at a crowned road's edge, 0.06-0.07 m under the vehicle's ground (ring 0,
  // embankment_s4803 frame 4). Level 1 takes a steep return down to 0.5 m under its plane
  // (LabelRule::down); down to 0.1 m for every steep return of the walk, or 0.18, a face
  // standing on a lower surface passed too (issue 10's session 61).
  float first_foot_under_m = 0.1f;
  float steep_climb_m = 0.7f;  // ... where it climbs at most this past its last ground return
  // ... and at most this where the profile climbs gently (under gentle_climb_gradient): a
  // climb that gentle is no bank face measured ring after ring but may be a fence's foot,
  // and carried 9 m it lifts the profile 0.3 m, onto a facade's foot (fences_s3805, 5 Hz).
  float gentle_steep_climb_m = 0.2f;
  float gentle_climb_gradient = 0.06f;
  float label_up_m = 0.18f, label_down_m = 0.5f;  // band for returns that do not advance
  // A ground return more than this over the level-2 surface stays ground only when the
  // ground return before or after it in its column is raised too (a bank rises over
  // several rings; a fence or a box side is one ring line), or when it is at most half of
  // this over the ground return before it or over the chord joining the ground returns
  // before and after it (then the level-2 surface is what is off), or when it lies over the
  // sensor, or is the column's first return, on a ring run at least rise_run_min_m long
  // where the level-2 surface has no ground of its own (terrain climbing over the sensor,
  // met by one ring far out where the cells only extrapolate; the street over a ramp's
  // parapet met by the lowest ring past everything; an object on a bank's top or a tree
  // crown is a shorter run: at 8 m, bank_s603_tilt took a shed's top; at 12 m, hills_s603
  // lost most of the gain).
  float single_rise_m = 0.3f;
  float rise_run_min_m = 10.f;
  // A return that bent the profile's gradient up by more than kink_gradient (a kink: hills
  // bend the profile by a few hundredths per metre) needs only to stand kink_rise_m (the
  // cells' label band) over the level-2 surface to count as a single rise (a low fence line
  // just past ground, 0.2-0.3 m up, would otherwise start a chain of fence lines).
  float kink_gradient = 0.1f, kink_rise_m = 0.18f;
  // ... and a raised ground return after it vouches for it only within kink_vouch_span x
  // its distance (the rise going on), not far beyond.
  float kink_vouch_span = 0.25f;
  // The walk takes a kink back (kink_was_an_object) when the next return that advances lies
  // more than drop_m under the profile the kink extrapolated, yet more than single_rise_m
  // over a level-2 surface fitted to ground of its own there: it is on no lower surface,
  // so the kink was a low object in front (a fence line 0.3 m up, a bush), not a bend of the
  // terrain; or when it lies on such a surface within single_rise_m of the ground before
  // the kink extrapolated, nearer to it than to the kink's height: the ground ran on under
  // the kink. The kink becomes an obstacle and the walk goes on from the ground before it.
  // Only a kink rising from that ground by keep_gradient_rise per metre or more is taken
  // back: one level with it is a descent levelling off.
  // Consecutive raised ground returns of a column along at most this, each more than drop_m
  // over the ground before and after them, are an object the walk climbed (a car roof, a
  // fence top seen by two rings), however they vouch for each other.
  float bump_group_max_m = 4.f;
  // ... unless they lie along at least this, rising on as the chord from the ground before
  // them does, with the ground after them more than drop_m under the ground before, or, as
  // the column's first ground, over a level-2 surface more than drop_m under the ground
  // under the vehicle: a crest's top (crest_top).
  float crest_min_m = 1.f;
  // A rise of the profile over single_rise_m between two ground returns of a column is
  // refuted by a ground return of a column at most this far to the side, between the two
  // in distance and more than single_rise_m under the profile (drop_refuted_rises).
  float refute_lateral_m = 0.4f;
  // Past an obstacle a return this close to a level-1 plane that explains its cell is ground
  // (the plane is trusted where it explains the ground; the cells' own fits are not).
  float plane_band_m = 0.1f;
  // A steep return within steep_band_m of such a plane and this close to the profile is
  // the foot of a wall on ground the profile does not quite follow (a slope).
  float plane_foot_m = 0.5f;
  // ... but the column's first return, over the start's level, only within this of it: a
  // building's foot on a pavement 0.17-0.23 m up stands; a ramp's wall the lowest ring met
  // higher over the vehicle's ground stands over ground it hides (garage_s603, garage_s907).
  float first_foot_over_m = 0.25f;
  // A steep return is no wall's foot where its column's lower ring met the same face more
  // than this much lower (face_goes_on_below).
  float face_below_m = 0.2f;
  // Runs along a ring: neighbours at most run_column_gap columns (one more where both lie
  // more than drop_m over the sensor) and run_gap_m + run_gap_per_m x range apart are
  // continuous; a run no longer than silhouette_max_m with both ends open (no return over
  // sky_columns columns, or the next return farther away) stands out as an object.
  int run_column_gap = 2;
  float run_gap_m = 0.3f, run_gap_per_m = 0.02f;
  float silhouette_max_m = 6.f;
  int sky_columns = 3;
  // ... and a run over the sensor up to wide_silhouette_max_m long, within
  // wide_silhouette_range_m, with the sky at both ends, where each end lies more than
  // wide_silhouette_past_lower times as far out as its column's ground return of the ring
  // below (the ground between unseen): the top of an object on a bank's top.
  float wide_silhouette_max_m = 8.f;
  float wide_silhouette_range_m = 50.f;
  float wide_silhouette_past_lower = 1.5f;
  // This frame is a fragment of a rotation going on from the previous frame labelled, a
  // whole rotation that ended at the cut (consecutive, nothing between): a ring's run at the
  // frame's first or last columns is judged with its part in the previous frame
  // (stands_out_with_past).
  bool continues_previous = false;
  // ... or, for a ring's ray rising over the sensor, the next return nearer still where the
  // ground it met there climbed from its column's last ground return more steeply than
  // face_over_ray x that ray (a bank's face): the ray would pass on beside that face only
  // over a step to the side (a bush or a shed on the bank's top seen past the face's end).
  float face_over_ray = 2.f;
  // Rays never pass under the ground (docs/detector.md, "Column profiles", rule 6): a return
  // is not ground when the ray of a lower ring of its column reaches it (returns at most
  // reach_slack_m nearer, or farther) more than under_ray_m under it, or when it climbs
  // more than sky_climb_m over the last ground return while the ray of a ring between the
  // two reached it or went to the sky (no return in its column, and none that ends short of
  // it in either neighbour): that ray would have hit any surface joining them.
  float under_ray_m = 0.2f, reach_slack_m = 0.1f;
  float sky_climb_m = 0.5f;
  // Shadows along a ring: returns of a continuous run that the walk refused only because an
  // obstacle stood in front of them in their columns (a trunk, a box, a car near the
  // sensor) are ground when they lie within shadow_band_m of the line joining the run's
  // ground on both sides of the shadow, and that ground is seen over at least
  // shadow_anchor_m on each side (a lone ground return on a fence line anchors nothing).
  // So are single rises under the ground the vehicle stands on (a levee's side).
  float shadow_band_m = 0.2f, shadow_anchor_m = 0.7f;
  // ... and over this where an object in front cuts that ground short at the run's end: the
  // ring steps back onto the run from a nearer return past the object's edge (steps_back).
  // Between such ground only returns refused past an obstacle are taken, not walls' feet.
  // The rule off: shadow_anchor_cut_m = shadow_anchor_m.
  float shadow_anchor_cut_m = 0.3f;
  // The vehicle's road behind an object's foot (rule 5, road_behind_object): carrying the
  // vehicle's road over road_behind_min_rad of the ring (at least road_behind_min_m, at most
  // shadow_anchor_m), the ring stepping back onto it past the object's edge by more than
  // edge_step_ratio times the distance across the rays and more than edge_step_min_m.
  float road_behind_min_m = 0.4f, road_behind_min_rad = 0.04f;
  float edge_step_ratio = 3.f, edge_step_min_m = 0.12f;
  // ... and, where the walk took the whole run, level with that road within this.
  float whole_run_level_m = 0.05f;
  // The vehicle's road seen through a gap in an object (drop_all_but_road_through_gaps):
  // level with the lower ring's road within whole_run_level_m, at most this farther.
  float gap_road_reach_m = 2.f;
  // A ring's line along a wall (drop_wall_lines): returns continuous along the ring with a
  // steep return high on its face and at most this under it are the wall too.
  float wall_line_band_m = 0.25f;
};

class ColumnProfiles {
 public:
  /// Labels every cloud point by its column's profile: ground[i] (0/1) and height[i] over
  /// the profile. On entry height[i] is the point's height over the level-2 surface (NaN:
  /// none); `plane_height` the same where that surface is a level-1 plane explaining its
  /// cell (NaN elsewhere). Allocates nothing once the buffers have grown to the largest frame.
  /// `level2`: where the level-2 surface has ground of its own.
  void label(const Cloud& cloud, const std::uint8_t* steep, const Level2Coverage& level2,
             const std::vector<float>& plane_height, const ProfileParams& params,
             std::vector<std::uint8_t>& ground, std::vector<float>& height);

 private:
  static constexpr std::uint32_t kNoPoint = 0xffffffffu;
  static constexpr std::uint8_t kShadow = 1, kFoot = 2;
  // A return as the walk sees it, gathered in column order.
  struct ColumnPoint {
    float r, z, level2_h;
    std::uint32_t index;  // cloud point
    std::uint8_t ring, steep, ground;
    // Refused only for an obstacle in front, or as a single rise under the vehicle's ground
    // (kShadow), or a steep return off the profile's steep band (kFoot): the ring may take
    // it (fill_shadows).
    std::uint8_t shadowed = 0;
    std::uint8_t rises_on = 0;  // resumed as ground over the sensor (rises_over_its_ray)
    // Taken as ground bending the profile's gradient up by more than kink_gradient.
    std::uint8_t kinked = 0;
    // Taken as ground past an obstacle (an obstacle return since the last ground return).
    std::uint8_t resumed = 0;
    // Taken only as level ground running on past a face (rises_on_over_sensor).
    std::uint8_t level_run = 0;
    // Taken by the walk, then dropped as a raised group (drop_raised_groups).
    std::uint8_t dropped = 0;
    // Level with the start, no obstacle before it in the column (the vehicle's ground).
    std::uint8_t vehicle_ground = 0;
    // ... and the cloud index of the column's next ground return when that goes on level
    // from it (a higher ring, nothing between): the road the vehicle stands on, seen by two
    // rings, unless that return stands out itself (remove_silhouettes).
    std::uint32_t road_beyond = kNoPoint;
  };
  void gather_by_column(const Cloud& cloud, const std::uint8_t* steep,
                        const std::vector<float>& level2_height, std::size_t strongest);
  void merge_layers();
  void note_ring_reach(std::size_t c);
  void walk_column(std::size_t column, std::size_t begin, std::size_t end,
                   const std::vector<float>& plane_height, std::vector<float>& height);
  [[nodiscard]] bool ray_returned_past(std::size_t column, int ring, float r) const;
  [[nodiscard]] bool ray_reaches(std::size_t column, int ring, float r) const;
  [[nodiscard]] bool bends_on(std::size_t k, std::size_t end, float step, float bend) const;
  [[nodiscard]] bool runs_on_measured_level2(std::size_t k, std::size_t end, float step) const;
  // No level ground running on past a face (rises_on_over_sensor's level_run_top).
  static constexpr float kNoLevelRun = -std::numeric_limits<float>::infinity();
  [[nodiscard]] bool rises_over_its_ray(std::size_t k, std::size_t end, bool past_faces_only,
                                        float level_run_top = kNoLevelRun) const;
  [[nodiscard]] bool rises_on_over_sensor(std::size_t k, std::size_t end,
                                          float level_run_top) const;
  [[nodiscard]] bool runs_on_in_line(std::size_t k, std::size_t end) const;
  [[nodiscard]] std::size_t next_advancing(std::size_t k, std::size_t end) const;
  [[nodiscard]] bool on_wall_top(float r, float z, float face_r, float face_z) const;
  [[nodiscard]] bool climbs_on_level2(std::size_t k, std::size_t end, float step) const;
  [[nodiscard]] bool rises_past_valley_floor(std::size_t k, std::size_t end, float gradient,
                                             float step, bool within_rise) const;
  [[nodiscard]] bool steepens_over_its_ray(std::size_t k, std::size_t end, float last_r,
                                           float last_z, float bend) const;
  [[nodiscard]] bool on_measured_level2(const ColumnPoint& q) const;
  [[nodiscard]] bool under_overhang(const ColumnPoint& q, const ColumnPoint& above) const;
  [[nodiscard]] bool face_over(const ColumnPoint& q, const ColumnPoint& over) const;
  [[nodiscard]] bool face_goes_on_below(std::size_t begin, std::size_t k) const;
  // The column's return of the next lower ring than column point k's (column points
  // [begin, k)), skipping the other layer's return of k's own ring; kNone: none. Inline: the
  // walk asks it of every steep return it would take as a wall's foot.
  [[nodiscard]] std::size_t lower_ring_return(std::size_t begin, std::size_t k) const {
    for (std::size_t j = k; j > begin; --j) {
      if (points_[j - 1].ring != points_[k].ring) return j - 1;
    }
    return kNone;
  }
  template <class Also>
  [[nodiscard]] bool level_overhang(std::size_t k, std::size_t end, float level_m, Also also) const;
  [[nodiscard]] bool under_level_overhang(std::size_t k, std::size_t end) const;
  [[nodiscard]] bool meets_underside_edge(std::size_t begin, std::size_t k, std::size_t end) const;
  [[nodiscard]] bool face_under(std::size_t begin, std::size_t j) const;
  [[nodiscard]] bool past_hidden_top(float r, float last_r, float last_z) const;
  [[nodiscard]] bool climb_levelled_off(float gradient, float step) const;
  [[nodiscard]] bool climb_is_guess(float gradient, float advance) const;
  [[nodiscard]] bool foot_climb_is_guess(float gradient, float advance) const;
  // An obstacle return lying `depth` under the profile's extrapolation (r < 0: none): the
  // ground at its distance lies at or under it.
  struct GroundBound {
    float r = -1.f, z = 0.f, depth = 0.f;
  };
  [[nodiscard]] GroundBound deepest_obstacle(std::size_t from, std::size_t k, float last_r,
                                             float last_z, float gradient) const;
  [[nodiscard]] bool rises_off_bound(float r, float z, float gradient,
                                     const GroundBound& bound) const;
  // The walk's state before its last ground return, kept while that return is a kink
  // (kink_was_an_object may take it back).
  struct BeforeKink {
    float last_r, last_z, gradient, gradient_r;
    int last_ring;
    std::size_t profile_size, last_ground;
  };
  [[nodiscard]] bool kink_was_an_object(std::size_t k, const BeforeKink& before,
                                        float kink_z) const;
  [[nodiscard]] bool is_ground_neighbour(std::size_t k) const;
  [[nodiscard]] static float gradient_between(const ColumnPoint& from, const ColumnPoint& to);
  [[nodiscard]] bool raised_over_level2(std::size_t k, float by) const;
  [[nodiscard]] bool stands_over_measured_level2(std::size_t k) const;
  [[nodiscard]] bool rise_refuted(const Cloud& cloud, std::size_t c, std::size_t a,
                                  std::size_t b) const;
  void drop_refuted_rises(const Cloud& cloud);
  // Whether it dropped any group.
  bool drop_raised_groups(std::size_t begin, std::size_t end);
  [[nodiscard]] bool top_at_column_end(std::size_t first, std::size_t last, bool column_first) const;
  [[nodiscard]] bool crest_top(std::size_t first, std::size_t last, std::size_t after,
                               float before_r, float before_z, bool from_start) const;
  [[nodiscard]] bool any_steep(std::size_t first, std::size_t last) const;
  void drop_orphaned_feet(std::size_t begin, std::size_t end);
  void check_single_rises(const Cloud& cloud, std::size_t begin, std::size_t end);
  [[nodiscard]] bool floor_under_face(std::size_t k, std::size_t end) const;
  [[nodiscard]] bool climbs_over_fallen_cells(std::size_t k, std::size_t next) const;
  [[nodiscard]] bool over_fallen_cells(const ColumnPoint& q) const;
  [[nodiscard]] bool on_ring_run_of(const Cloud& cloud, std::size_t i, float min_m) const;
  void find_ring_runs(const Cloud& cloud, std::size_t strongest_end);
  void remove_silhouettes(const Cloud& cloud);
  void drop_short_level_runs(const Cloud& cloud);
  struct RingRun;
  void fill_shadows(const Cloud& cloud, const RingRun& run,
                    std::vector<std::uint8_t>& ground) const;
  // How far a ground stretch of a ring run is seen (fill_shadows): not far enough, over
  // shadow_anchor_cut_m where an object cuts it short, over shadow_anchor_m.
  enum class Anchor : std::uint8_t { none, cut_short, full };
  void fill_between(const Cloud& cloud, std::size_t a, std::size_t b,
                    std::vector<std::uint8_t>& ground, bool feet) const;
  [[nodiscard]] Anchor ground_from(const Cloud& cloud, const std::vector<std::uint8_t>& ground,
                                   std::size_t i, std::size_t end, std::size_t last) const;
  void mark_continuous(const Cloud& cloud, std::size_t end);
  [[nodiscard]] bool bridged_over_sensor(const Cloud& cloud, std::size_t a) const;
  [[nodiscard]] bool stands_out(const Cloud& cloud, std::size_t first, std::size_t last,
                                std::size_t a, std::size_t b) const;
  [[nodiscard]] bool wide_silhouette(const Cloud& cloud, std::size_t first, std::size_t last,
                                     std::size_t a, std::size_t b, float extent) const;
  [[nodiscard]] bool far_past_lower_ground(const Cloud& cloud, std::size_t end) const;
  [[nodiscard]] std::size_t lower_ring_ground(const Cloud& cloud, std::size_t end) const;
  // The ring's return beyond a run's end (kNone: none known), the columns without a return
  // between them, and whether it lies across the frame's edge (its range then off by the
  // vehicle's motion over the rotation).
  struct RingBeyond {
    std::size_t index;
    int gap;
    bool across = false;
  };
  [[nodiscard]] RingBeyond beyond_end(const Cloud& cloud, std::size_t first, std::size_t last,
                                      std::size_t end, bool after) const;
  [[nodiscard]] std::size_t across_edge(const Cloud& cloud, std::size_t first, std::size_t last,
                                        std::size_t end, bool after, int& around) const;
  [[nodiscard]] bool end_open(const Cloud& cloud, std::size_t end, const RingBeyond& beyond,
                              bool face = false) const;
  [[nodiscard]] bool under_lower_ground(const Cloud& cloud, std::size_t end) const;
  [[nodiscard]] bool outer_end_sky(const Cloud& cloud, const RingRun& run, bool after) const;
  void drop_wall_lines(const Cloud& cloud);
  void drop_covered_tops(const Cloud& cloud);
  [[nodiscard]] bool nothing_taken_over(const Cloud& cloud, std::size_t i) const;
  [[nodiscard]] bool across_the_rays(const Cloud& cloud, std::size_t a, std::size_t b) const;
  [[nodiscard]] bool ground_and_face(const RingRun& run) const;
  void follow_wall_lines(const Cloud& cloud, const RingRun& run, bool forward);
  // How high a steep return lies on its face (face_height): low (near its foot, or no lower
  // ring met the face), high (more than drop_m over a lower ring's return on it), on_object
  // (over one that is itself an obstacle on the face: two rings tall); unknown: not asked.
  enum class FaceHeight : std::uint8_t { unknown, low, high, on_object };
  [[nodiscard]] FaceHeight face_height(const Cloud& cloud, std::size_t k) const;
  void mark_broken_silhouettes(const Cloud& cloud);
  void mark_chained_silhouettes(const Cloud& cloud);
  void mark_silhouettes_across_objects(const Cloud& cloud);
  [[nodiscard]] std::size_t run_past_object(const Cloud& cloud, std::size_t i) const;
  [[nodiscard]] bool stands_out_across_object(const Cloud& cloud, const RingRun& one,
                                              const RingRun& two) const;
  [[nodiscard]] bool joined_across_small_cut(const Cloud& cloud, std::size_t i) const;
  [[nodiscard]] bool runs_raised(std::size_t i, std::size_t j) const;
  [[nodiscard]] bool sky_past_both_ends(const Cloud& cloud, const RingRun& first,
                                        const RingRun& last) const;
  [[nodiscard]] bool face_over_line(const Cloud& cloud, const RingRun& first,
                                    const RingRun& last) const;
  void mark_hidden_silhouettes(const Cloud& cloud);
  [[nodiscard]] bool hidden_run(const Cloud& cloud, const RingRun& run) const;
  [[nodiscard]] bool falls_out_of_reach_past(const Cloud& cloud, const RingRun& run,
                                             std::size_t end, const RingBeyond& beyond) const;
  [[nodiscard]] bool at_one_range(const Cloud& cloud, const RingRun& run) const;
  [[nodiscard]] bool at_one_range(const Cloud& cloud, std::size_t a, std::size_t b) const;
  struct RangeSpread {
    float nearest, farthest;
  };
  [[nodiscard]] static RangeSpread range_spread(const Cloud& cloud, std::size_t a, std::size_t b);
  [[nodiscard]] float distance_across_rays(const Cloud& cloud, std::size_t a, std::size_t b) const;
  [[nodiscard]] bool level_with_start(const RingRun& run) const;
  [[nodiscard]] bool falls_away_past(const Cloud& cloud, std::size_t end,
                                     const RingBeyond& beyond) const;
  [[nodiscard]] bool lone_before_sky(const Cloud& cloud, std::size_t first, std::size_t last,
                                     std::size_t i, bool after) const;
  [[nodiscard]] bool hidden_by_object(const Cloud& cloud, std::size_t first, std::size_t last,
                                      std::size_t end, const RingBeyond& beyond, bool after) const;
  [[nodiscard]] std::size_t next_run(std::size_t i) const;
  void mark_standing_out(const RingRun& run);
  // The run gap at horizontal range `range_m`: run_gap_m + run_gap_per_m x range.
  [[nodiscard]] float run_gap(float range_m) const { return p_.run_gap_m + p_.run_gap_per_m * range_m; }
  // Whether a ring's next return at range beyond_m lies behind one at end_m (a run's end
  // opening onto it).
  [[nodiscard]] bool farther(float end_m, float beyond_m) const {
    return beyond_m > end_m + p_.run_gap_m;
  }
  // ... where the two lie across the frame's edge: by more than the motion slack
  // (kEdgeMotionSlack run gaps) on top.
  [[nodiscard]] bool farther(float end_m, float beyond_m, bool across) const {
    return across ? beyond_m > end_m + kEdgeMotionSlack * run_gap(end_m) : farther(end_m, beyond_m);
  }
  [[nodiscard]] bool stopped_by_face(const Cloud& cloud, std::size_t end,
                                     std::size_t nearer) const;
  [[nodiscard]] bool falls_across_edge(const Cloud& cloud, std::size_t end,
                                       const RingBeyond& across, const RingBeyond& other) const;
  void add_to_profile(float r, float z);
  [[nodiscard]] float profile_at(float r) const;

  ProfileParams p_;
  const std::uint8_t* steep_ = nullptr;  // the frame's steep flags, by cloud point (label)
  Level2Coverage level2_;  // where the level-2 surface has ground of its own (label)
  float start_z_ = 0.f;  // the ground under the vehicle, where every column starts
  // The ground returns walked in the current column (the start under the sensor first).
  std::array<float, 2 * kLasers + 1> profile_r_{}, profile_z_{};
  std::size_t profile_size_ = 0;
  std::vector<std::uint32_t> column_start_;
  std::vector<ColumnPoint> points_;
  std::vector<std::uint32_t> position_;  // column point of each cloud point
  std::vector<float> ring_reach_;        // farthest return by column and ring (ray_reaches)
  std::vector<std::uint8_t> shadowed_;   // ColumnPoint::shadowed by cloud point
  std::vector<std::uint32_t> refuted_;   // column points to drop (drop_refuted_rises)
  // Returns past a hidden top (past_hidden_top) this frame, as cloud index x 2 + 1 where the
  // walk took it with a face or crown over it (covered), + 0 where it refused it as its
  // column's last return (bare) (drop_covered_tops).
  std::vector<std::uint64_t> hidden_tops_;
  std::vector<std::uint8_t> stands_out_;  // in a run standing out (remove_silhouettes)
  std::vector<std::uint8_t> continuous_;  // with the next return (mark_continuous)
  // A run [a, b] of returns continuous along a ring whose returns are [first, last). A ring
  // is a closed curve that the frame's edge cuts: the ring's first run goes on from its last
  // run across the edge when their ends are continuous (wrap: the other run's index).
  static constexpr std::size_t kNoRun = ~std::size_t{0};
  static constexpr std::size_t kNone = ~std::size_t{0};  // no such point position
  // Two returns across the frame's edge are neighbours where their azimuths are at most this
  // many times their column gap apart (the frame a whole rotation there).
  static constexpr float kAzimuthSlack = 1.5f;
  // A frame of fewer columns is a fragment (a capture's last, or one cut short by lost
  // packets), never a whole rotation: every VLP-16 rotation has 904 columns or more (20 Hz),
  // and the azimuth test above, against a column step of a full turn over the frame's
  // columns, takes the two ends of a fragment of up to 73 columns for neighbours (at 5 Hz's
  // 0.1 degree steps; slope_s5601's last frame at 20 Hz: 36 columns, 14 degrees). Asked by
  // falls_across_edge only: refusing such neighbours everywhere lowered F1 on 260 of 6270
  // tuning captures (jam at Hi-Res most, whose last fragment's runs stood out against the
  // fragment's other end) and raised it on 55.
  static constexpr int kMinRotationColumns = 100;
  // Returns across the frame's edge are continuous within this many times the run gap (the
  // vehicle moved over the rotation between them).
  static constexpr float kEdgeMotionSlack = 2.f;
  struct RingRun {
    std::size_t first, last, a, b;
    std::size_t wrap = kNoRun;
  };
  [[nodiscard]] bool continuous_across_edge(const Cloud& cloud, std::size_t end,
                                            std::size_t start) const;
  [[nodiscard]] bool under_half_turn(const Cloud& cloud, std::size_t a, std::size_t b) const;
  [[nodiscard]] bool turns_under_half(const Cloud& cloud, std::size_t a, std::size_t b) const;
  void remove_silhouette(const Cloud& cloud, const RingRun& run, const RingRun* before);
  [[nodiscard]] bool carries_vehicle_road(const Cloud& cloud, std::size_t i,
                                          float level_m = std::numeric_limits<float>::max()) const;
  [[nodiscard]] bool goes_on_from_road(const Cloud& cloud, std::size_t i, float level_m,
                                       float reach_m) const;
  [[nodiscard]] bool road_behind_object(const Cloud& cloud, const RingRun& run, std::size_t& keep_a,
                                        std::size_t& keep_b) const;
  // Whether return i (cloud index, strongest layer) is ground by the walk, not dropped since.
  [[nodiscard]] bool taken(std::size_t i) const { return points_[position_[i]].ground != 0; }
  // Whether cloud return i is its column's first point (the lowest ring there, in walking order).
  [[nodiscard]] bool first_in_column(const Cloud& cloud, std::size_t i) const {
    return position_[i] == column_start_[cloud.column[i]];
  }
  void drop_run(const RingRun& run, std::size_t keep_a, std::size_t keep_b);
  void drop_all_but_road_through_gaps(const Cloud& cloud, const RingRun& run);
  // The ring's returns just past a run's two ends, and the run's first and last returns the
  // walk refused (between_feet); kNone where there are none.
  struct BetweenFeet {
    std::size_t past_before = kNone, past_after = kNone;
    std::size_t first_refused = kNone, last_refused = kNone;
  };
  [[nodiscard]] BetweenFeet between_feet(const RingRun& run) const;
  [[nodiscard]] bool on_ground_between_feet(const Cloud& cloud, const BetweenFeet& feet,
                                            std::size_t i) const;
  [[nodiscard]] bool steps_back(const Cloud& cloud, std::size_t near, std::size_t far) const;
  [[nodiscard]] bool steps_behind(const Cloud& cloud, std::size_t near, std::size_t far,
                                  std::size_t next) const;
  [[nodiscard]] float road_anchor(float range_m) const;
  std::vector<RingRun> runs_;  // every ring's runs (strongest layer), in ring order
  // The previous frame's points_ and column_start_, swapped out at the end of label (no
  // copy), for a fragment going on from it (ProfileParams::continues_previous); and the end
  // of its strongest layer's cloud points.
  std::vector<ColumnPoint> past_points_;
  std::vector<std::uint32_t> past_column_start_;
  std::size_t past_strongest_end_ = 0;
  void keep_past(std::size_t strongest_end);
  // The previous frame's strongest return of `ring` in column c (kNone: none).
  [[nodiscard]] std::size_t past_on_ring(int c, int ring) const;
  // Columns of this frame and of the previous one (column starts hold one more entry).
  [[nodiscard]] static int columns_of(const std::vector<std::uint32_t>& starts) {
    return starts.empty() ? 0 : static_cast<int>(starts.size()) - 1;
  }
  [[nodiscard]] int frame_columns() const { return columns_of(column_start_); }
  [[nodiscard]] int past_columns() const { return columns_of(past_column_start_); }
  // Whether the run ending at cloud point i goes on into the previous frame (going on to
  // higher columns, or back across the cut) and ends open there; `extent` gets the length
  // of the part there.
  [[nodiscard]] bool past_part_open(const Cloud& cloud, std::size_t i, bool forward,
                                    float& extent) const;
  [[nodiscard]] bool stands_out_with_past(const Cloud& cloud, const RingRun& run) const;
};

// Shared by level 3's files (column_walk.cpp, ring_runs.cpp, ring_lines.cpp,
// column_rises.cpp).

// A ground return of its column that may vouch for its neighbours (rule 4): not on a steep
// surface taken for the foot of a wall.
inline bool ColumnProfiles::is_ground_neighbour(std::size_t k) const {
  return points_[k].ground != 0 && points_[k].steep == 0;
}

// The gradient (rise per metre of range) along the column from return `from` to `to`.
inline float ColumnProfiles::gradient_between(const ColumnPoint& from, const ColumnPoint& to) {
  return (to.z - from.z) / (to.r - from.r);
}

// Whether return k lies more than `by` over the level-2 surface.
inline bool ColumnProfiles::raised_over_level2(std::size_t k, float by) const {
  const float h = points_[k].level2_h;
  return std::isfinite(h) && h > by;
}

// Whether return k lies more than single_rise_m over the level-2 surface where that surface
// has ground of its own (Level2Coverage::measured, looked up only for a return that high).
inline bool ColumnProfiles::stands_over_measured_level2(std::size_t k) const {
  return raised_over_level2(k, p_.single_rise_m) && level2_.measured(points_[k].index);
}

// The nearest and farthest horizontal range of returns [a, b].
inline ColumnProfiles::RangeSpread ColumnProfiles::range_spread(const Cloud& cloud, std::size_t a,
                                                                std::size_t b) {
  const float* const range = cloud.range_xy.data();
  RangeSpread spread{range[a], range[a]};
  for (std::size_t i = a + 1; i <= b; ++i) {
    spread.nearest = std::min(spread.nearest, range[i]);
    spread.farthest = std::max(spread.farthest, range[i]);
  }
  return spread;
}

// The horizontal distance across the rays between returns a and b, at b's range.
inline float ColumnProfiles::distance_across_rays(const Cloud& cloud, std::size_t a,
                                                  std::size_t b) const {
  const float ax = cloud.x[a] - p_.sensor_x, ay = cloud.y[a] - p_.sensor_y;
  const float bx = cloud.x[b] - p_.sensor_x, by = cloud.y[b] - p_.sensor_y;
  return std::abs(ax * by - ay * bx) / cloud.range_xy[b];
}

// Whether returns a and b lie at least `distance` apart horizontally.
inline bool apart(const Cloud& cloud, std::size_t a, std::size_t b, float distance) {
  const float dx = cloud.x[b] - cloud.x[a], dy = cloud.y[b] - cloud.y[a];
  return dx * dx + dy * dy >= distance * distance;
}

}  // namespace vlpground::detail
