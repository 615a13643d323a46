// Level 3 along the rings (docs/detector.md, "Column profiles", rule 5): a ring's line along
// a wall carries the wall on, a ring's object past a hidden top is one object, and a ring
// runs on as ground across the shadow of an obstacle in front.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "column_profile.hpp"

namespace vlpground::detail {

using Index = std::size_t;

namespace {
// face_height: a hit this far over a lower ring's hit on the same face, itself an obstacle.
constexpr float kFaceTwoRings_m = 0.4f;
}  // namespace

// A ring's line along a wall: a steep obstacle return high on its face (a lower ring of its
// column met the same face, within the run gap in range, more than drop_m lower) carries
// the object along its ring: the ground returns that follow it along the ring (in its run,
// either way) level with it (at most wall_line_band_m under it, or over it) are that object
// too, seen where no lower ring meets the face in their columns (a shed on a bank's top,
// whose face the bank hides from the rings below: bank_s101 at Hi-Res). The line ends at a
// steep return that is not high on its face (the ring came down to the face's foot), at a
// ground return under the band, and at an obstacle return that is not steep: where a ring
// runs along a ramp's retaining wall onto the street on its top, it crosses the wall's top
// edge first (garage_s2). It crosses such obstacle returns only where the face is two rings
// tall (the lower ring's return on it is itself an obstacle on a steep face) and they lie
// level with the face within the band and at its range within the run gap: the object's
// own returns where the walk saw it rise too fast to be ground but no ring pair met it
// steeply (a tall vehicle's side in a jam, jam_s702 at 5 Hz; an object on a bank's top). The ground
// it takes past them lies within the band both ways: a bank rising on past a low object's top is
// not its line.
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

// A ring meeting an object that stands on a top the rings cannot see: the walk refuses the
// ring's returns where they are their column's last (past_hidden_top: bare) and takes
// them where the next ring rises over them more steeply than any ground, meeting the
// object's face or crown (covered, hidden_tops_). A short run (silhouette_max_m, the chord
// between its ends), more across the rays than along them, with a bare return is that one
// object: its covered returns with no return over them taken (nothing_taken_over) leave
// the ground too (bank_s6701: ring 11 on an object 31-32 m out, 2 m over the top of a bank
// that ring 10 met 17 m out, ring 12 on it 1.5 m higher over 16 of the run's 26 columns).
// A long run is a hillside rising on far past a hidden dip, where a few objects over it
// cover some columns (hills_s903: ring 11 along a hill 38 m out over 93 columns); one
// receding along the rays, a hillside along the ring (hills_s5904 tilted).
void ColumnProfiles::drop_covered_tops(const Cloud& cloud) {
  const auto index = [](std::uint64_t mark) { return static_cast<Index>(mark >> 1); };
  const auto covered_mark = [](std::uint64_t mark) { return (mark & 1u) != 0; };
  // Most frames have none.
  if (std::none_of(hidden_tops_.begin(), hidden_tops_.end(), covered_mark)) return;
  std::sort(hidden_tops_.begin(), hidden_tops_.end());  // a few, in cloud order (as the runs)
  std::size_t m = 0;
  for (const RingRun& run : runs_) {
    while (m < hidden_tops_.size() && index(hidden_tops_[m]) < run.a) ++m;
    std::size_t end = m;  // [m, end): the run's marks
    bool bare = false, covered = false;
    for (; end < hidden_tops_.size() && index(hidden_tops_[end]) <= run.b; ++end) {
      (covered_mark(hidden_tops_[end]) ? covered : bare) = true;
    }
    if (bare && covered && !apart(cloud, run.a, run.b, p_.silhouette_max_m) &&
        across_the_rays(cloud, run.a, run.b)) {
      for (std::size_t k = m; k < end; ++k) {
        const Index i = index(hidden_tops_[k]);
        if (covered_mark(hidden_tops_[k]) && nothing_taken_over(cloud, i)) {
          points_[position_[i]].ground = 0;
        }
      }
    }
    m = end;
  }
}

// Whether returns a..b of one ring lie on a face more across the rays than along them:
// their spread in range at most the distance across the rays between the two ends.
bool ColumnProfiles::across_the_rays(const Cloud& cloud, Index a, Index b) const {
  const RangeSpread spread = range_spread(cloud, a, b);
  return spread.farthest - spread.nearest <= distance_across_rays(cloud, a, b);
}

// Whether no return of cloud point i's column over it (after it in the column) is ground.
bool ColumnProfiles::nothing_taken_over(const Cloud& cloud, Index i) const {
  const Index end = column_start_[cloud.column[i] + 1];
  for (Index k = position_[i] + 1; k < end; ++k) {
    if (points_[k].ground != 0) return false;
  }
  return true;
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
  // The last steep obstacle return of the line (kNone: no line) and how high it is on its
  // face, asked only when a return that is not steep follows it (walls are long).
  Index face = kNone;
  auto height = FaceHeight::unknown;
  bool crossed = false;  // the line crossed obstacle returns that are not steep
  for (Index n = 0; n <= run.b - run.a; ++n) {
    const Index k = position_[forward ? run.a + n : run.b - n];
    const ColumnPoint& q = points_[k];
    if (q.steep != 0) {  // the face goes on: high on it, or down to its foot
      face = q.ground == 0 ? k : kNone;
      height = FaceHeight::unknown;
      crossed = false;
      continue;
    }
    if (face == kNone) continue;
    const float face_z = points_[face].z, band = p_.wall_line_band_m;
    if (q.z < face_z - band || (q.ground == 0 && q.z > face_z + band)) {
      face = kNone;
      continue;
    }
    if (height == FaceHeight::unknown) height = face_height(cloud, face);
    if (q.ground != 0 && height != FaceHeight::low && (!crossed || q.z <= face_z + band)) {
      refuted_.push_back(static_cast<std::uint32_t>(k));
      continue;
    }
    if (q.ground == 0 && height == FaceHeight::on_object &&
        std::abs(q.r - points_[face].r) <= run_gap(q.r)) {
      crossed = true;
      continue;
    }
    face = kNone;
  }
}

// How high column point k (steep) lies on its face: more than drop_m over a lower ring's
// return of its column on the same face (within the run gap in range), or more than
// kFaceTwoRings_m over one that is itself an obstacle on a steep face (on_object): the face
// is then two rings tall, and rings 1.33 degrees apart (Puck Hi-Res) meet it only 0.45 m
// apart 20 m out (bank_s105).
ColumnProfiles::FaceHeight ColumnProfiles::face_height(const Cloud& cloud, Index k) const {
  const ColumnPoint& q = points_[k];
  const Index begin = column_start_[cloud.column[q.index]];
  const float gap = run_gap(q.r);
  auto height = FaceHeight::low;
  for (Index j = begin; j < k; ++j) {
    const ColumnPoint& low = points_[j];
    if (low.ring >= q.ring || std::abs(low.r - q.r) > gap) continue;
    if (low.steep != 0 && low.ground == 0 && q.z - low.z > kFaceTwoRings_m)
      return FaceHeight::on_object;
    if (q.z - low.z > p_.drop_m) height = FaceHeight::high;
  }
  return height;
}

// A run of one ring: an obstacle near the sensor (a trunk, a box, a car) hides the lower
// rings of the columns behind it, and the walk refuses the ground a higher ring sees past
// it when that ground has risen more than the allowance past an obstacle (the far side of a
// bowl, a hill behind a tree). The ring itself runs on across the shadow: a stretch of such
// returns with ground on both sides is ground where it lies on the line joining that
// ground. The ground on each side must be seen over shadow_anchor_m, so that a lone ground
// return on a fence line anchors nothing; over shadow_anchor_cut_m where an object in front
// cuts that ground short at the run's end (the ring steps back onto the run from a nearer
// return past the object's edge: a second object beside the one casting the shadow,
// hills_s4); between such ground the feet of walls (kFoot) are not taken (a face's foot
// past a car, urban_s205_hires). Single rises (rule 4) under the ground the vehicle stands
// on are taken the same way: a ring grazing a levee's side where the level-2 surface was
// fitted to the fields below.
void ColumnProfiles::fill_shadows(const Cloud& cloud, const RingRun& run,
                                  std::vector<std::uint8_t>& ground) const {
  const Index begin = run.a, end = run.b + 1;
  int begin_cut = -1;  // whether an object cuts the run at its beginning (-1: not asked yet)
  const auto cut_at_begin = [&] {
    if (begin_cut < 0) begin_cut = begin > run.first && steps_back(cloud, begin - 1, begin);
    return begin_cut != 0;
  };
  Index anchor = end;  // last return of a long enough ground stretch before a shadow
  Index start = end;   // first return of the ground stretch being walked
  Anchor stretch = Anchor::none;      // how far the stretch being walked is seen so far
  Anchor anchor_seen = Anchor::none;  // ... and the stretch of `anchor`
  for (Index i = begin; i < end; ++i) {
    if (ground[i] == 0) {
      start = end;
      stretch = Anchor::none;
      if (shadowed_[i] == 0) anchor = end;  // an obstacle of the ring itself
      continue;
    }
    if (start == end) start = i;
    // The first ground return past a shadow: the ground beyond it must be long enough too.
    if (anchor != end && i > anchor + 1 && ground[i - 1] == 0) {
      const Anchor beyond = ground_from(cloud, ground, i, end, run.last);
      // Feet of walls (kFoot) only between ground seen over shadow_anchor_m on both sides.
      if (beyond != Anchor::none)
        fill_between(cloud, anchor, i, ground, std::min(anchor_seen, beyond) == Anchor::full);
    }
    if (stretch != Anchor::full && apart(cloud, start, i, p_.shadow_anchor_m)) {
      stretch = Anchor::full;
    } else if (stretch == Anchor::none && start == begin &&
               apart(cloud, start, i, p_.shadow_anchor_cut_m) && cut_at_begin()) {
      stretch = Anchor::cut_short;
    }
    if (stretch != Anchor::none) anchor = i, anchor_seen = stretch;
  }
}

// The returns between ground returns a and b (same ring) become ground when every refused
// one lies within shadow_band_m of the line joining a and b (by column); the foot of a wall
// (where `feet`) within steep_band_m of it, as on the profile.
void ColumnProfiles::fill_between(const Cloud& cloud, Index a, Index b,
                                  std::vector<std::uint8_t>& ground, bool feet) const {
  const float z0 = cloud.z[a], z1 = cloud.z[b];
  const float span = static_cast<float>(cloud.column[b] - cloud.column[a]);
  for (Index k = a + 1; k < b; ++k) {
    if (ground[k] != 0) continue;
    const bool foot = shadowed_[k] == kFoot;
    if (foot && !feet) return;
    const float t = static_cast<float>(cloud.column[k] - cloud.column[a]) / span;
    const float band = foot ? p_.steep_band_m : p_.shadow_band_m;
    if (std::abs(cloud.z[k] - (z0 + t * (z1 - z0))) > band) return;
  }
  std::fill(ground.begin() + static_cast<std::ptrdiff_t>(a) + 1,
            ground.begin() + static_cast<std::ptrdiff_t>(b), std::uint8_t{1});
}

// How far the ground returns of the run from i (before `end`, the ring's returns ending at
// `last`) are seen: over shadow_anchor_m from it (full), or over shadow_anchor_cut_m where
// they run on to `end` and an object cuts the run there (cut_short).
inline ColumnProfiles::Anchor ColumnProfiles::ground_from(const Cloud& cloud,
                                                          const std::vector<std::uint8_t>& ground,
                                                          Index i, Index end, Index last) const {
  Index j = i;
  for (; j < end && ground[j] != 0; ++j) {
    if (apart(cloud, i, j, p_.shadow_anchor_m)) return Anchor::full;
  }
  const bool cut = j == end && end < last && apart(cloud, i, end - 1, p_.shadow_anchor_cut_m) &&
                   steps_back(cloud, end, end - 1);
  return cut ? Anchor::cut_short : Anchor::none;
}

}  // namespace vlpground::detail
