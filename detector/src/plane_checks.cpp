#include "plane_checks.hpp"

#include <algorithm>
#include <cmath>

#include "tangents.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

Index idx(int v) { return static_cast<Index>(v); }

float plane_z(const Plane& p, float x, float y) { return -(p.nx * x + p.ny * y + p.d) / p.nz; }
float slope_x(const Plane& p) { return -p.nx / p.nz; }
float slope_y(const Plane& p) { return -p.ny / p.nz; }
float plane_gap(const Plane& a, const Plane& b, float x, float y) {
  return std::abs(plane_z(a, x, y) - plane_z(b, x, y));
}

int segment_of(const GroundResult& out, float x, float y) {
  return (x >= out.centre_x_m ? 1 : 0) + (y >= out.centre_y_m ? 2 : 0);
}

// The sensor-height prior: h, the sensor's height over the plane, within
// min..max_sensor_height_m; with the mounting height known, also at least the mounting
// height less max_over_wheels_m.
bool plausible_height(const AgreementRules& r, const Plane& p) {
  const double h = signed_height(p, r.origin_x, r.origin_y, r.sensor_z);
  const float min_m = static_cast<float>(r.min_sensor_height_m);
  const double lowest = mounting_height_known(r.sensor_z, min_m)
                            ? std::max(r.min_sensor_height_m, r.sensor_z - r.max_over_wheels_m)
                            : r.min_sensor_height_m;
  return h >= lowest && h <= r.max_sensor_height_m;
}

// Adjacent segments with their own ground must also agree along their shared edge (at
// 5, 10, 15 m from the centre, inside the fit radius); otherwise the higher one
// (never the anchor) loses its ground. A tilted plane through car sides or a facade can
// meet the anchor at the centre yet rise a metre above the terrain further out.
void check_edges(const AgreementRules& rules, int anchor, GroundResult& out) {
  // Pairs sharing the line x = cx (direction +-y) or y = cy (direction +-x).
  constexpr int kPairs[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};
  constexpr float kDir[4][2] = {{0, -1}, {0, 1}, {-1, 0}, {1, 0}};
  for (int k = 0; k < 4; ++k) {
    GroundSegment& a = out.segments[idx(kPairs[k][0])];
    GroundSegment& b = out.segments[idx(kPairs[k][1])];
    if (!a.has_ground || !b.has_ground) continue;
    float worst = 0;  // signed: a's height minus b's where they differ most
    for (float dist : {5.f, 10.f, 15.f}) {
      const float x = out.centre_x_m + kDir[k][0] * dist, y = out.centre_y_m + kDir[k][1] * dist;
      if (std::hypot(x - rules.origin_x, y - rules.origin_y) > rules.radius_m) break;
      const float diff = plane_z(a.plane, x, y) - plane_z(b.plane, x, y);
      if (std::abs(diff) > std::abs(worst)) worst = diff;
    }
    // Slack across the edge: the terrain break may sit a few metres off the cut line.
    const float across =
        kDir[k][0] != 0 ? slope_y(a.plane) - slope_y(b.plane) : slope_x(a.plane) - slope_x(b.plane);
    if (std::abs(worst) - rules.soft_m * std::abs(across) <= rules.max_step_m) continue;
    // Ground is the lower envelope: the plane riding higher is the implausible one.
    int loser = worst > 0 ? kPairs[k][0] : kPairs[k][1];
    if (loser == anchor) loser = kPairs[k][0] + kPairs[k][1] - loser;
    out.segments[idx(loser)].has_ground = false;
  }
}

// Net score (b_m of Algorithm 1: eq. 3 inliers minus the below penalty) of plane p over
// the scoring candidates of the bins of segment s of the partition.
std::int64_t segment_fit(const SearchResult& f, const SegmentEvidence& e, int s, const Plane& p) {
  const int c0 = (s & 1) ? f.centre_col : 0, c1 = (s & 1) ? e.bins : f.centre_col;
  const int r0 = (s & 2) ? f.centre_row : 0, r1 = (s & 2) ? e.bins : f.centre_row;
  const Candidates& q = *e.candidates;
  const ScoreParams& sp = e.score;
  std::int64_t sum = 0;
  for (int r = r0; r < r1; ++r)
    for (int c = c0; c < c1; ++c) {
      const std::int32_t slot = e.bin_slot[idx(r * e.bins + c)];
      if (slot < 0) continue;
      for (Index k = idx(q.start[idx(slot)]); k < idx(q.start[idx(slot) + 1]); ++k) {
        sum +=
            eq3_inlier(p, q.x[k], q.y[k], q.z[k], q.tx[k], q.ty[k], q.tz[k], sp.eps, sp.sin_delta);
        if (signed_height(p, q.x[k], q.y[k], q.z[k]) < sp.below) sum -= sp.penalty;
      }
    }
  return sum;
}

}  // namespace

void check_agreement(const SearchResult& f, const AgreementRules& rules, GroundResult& out) {
  int anchor = -1;
  for (int s = 0; s < 4; ++s) {
    const GroundSegment& g = out.segments[idx(s)];
    if (!g.has_ground || !plausible_height(rules, g.plane)) continue;
    if (anchor < 0 || f.score[idx(s)] > f.score[idx(anchor)]) anchor = s;
  }
  if (anchor < 0) {
    for (GroundSegment& g : out.segments) g.has_ground = false;
    return;
  }
  GroundSegment& own = out.segments[idx(segment_of(out, rules.origin_x, rules.origin_y))];
  if (!plausible_height(rules, own.plane)) own.has_ground = false;
  const Plane& a = out.segments[idx(anchor)].plane;
  for (GroundSegment& g : out.segments) {
    if (!g.has_ground) continue;
    // The planes must come within max_step_m of each other within soft_m of the centre:
    // the gap there shrinks by at most soft_m times the gradient of their difference.
    const float gap = plane_gap(g.plane, a, out.centre_x_m, out.centre_y_m);
    const float gradient = std::hypot(slope_x(g.plane) - slope_x(a), slope_y(g.plane) - slope_y(a));
    if (gap - rules.soft_m * gradient > rules.max_step_m) g.has_ground = false;
  }
  check_edges(rules, anchor, out);
}

// A far segment beyond a grade change takes the plane of the segment across the cut along
// the slope, not the larger one across the grade.
void inherit_planes(const SearchResult& f, const SegmentEvidence& evidence, GroundResult& out) {
  bool own[4];
  for (int s = 0; s < 4; ++s) own[s] = out.segments[idx(s)].has_ground;
  for (int s = 0; s < 4; ++s) {
    if (own[s]) continue;
    int donor = -1;
    std::int64_t best_fit = 0;
    for (int o : {s ^ 1, s ^ 2, s ^ 3}) {
      if (!own[o]) continue;
      const std::int64_t fit = segment_fit(f, evidence, s, out.segments[idx(o)].plane);
      if (donor < 0 || fit > best_fit ||
          (fit == best_fit && f.score[idx(o)] > f.score[idx(donor)])) {
        donor = o;
        best_fit = fit;
      }
    }
    if (donor < 0) continue;
    out.segments[idx(s)].plane = out.segments[idx(donor)].plane;
    out.segments[idx(s)].inherited = true;
  }
}

}  // namespace vlpground::detail
