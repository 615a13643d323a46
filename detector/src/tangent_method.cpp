// The paper's method ("tangent"): eq. 3 inlier test with ring tangents, RANSAC hypotheses,
// disjoint cross partition found by Algorithm 1 over integral images, plus the
// plausibility additions documented in docs/detector.md.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>

#include "binning.hpp"
#include "hypotheses.hpp"
#include "labelling.hpp"
#include "method.hpp"
#include "partition_search.hpp"
#include "ring_reach.hpp"
#include "scoring.hpp"
#include "steep.hpp"
#include "tangents.hpp"

namespace vlpground::detail {

namespace {

using Clock = std::chrono::steady_clock;
using Index = std::size_t;

Index idx(int v) { return static_cast<Index>(v); }

double ms_since(Clock::time_point& t) {
  const auto now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

constexpr float kDegToRad = static_cast<float>(M_PI / 180.0);
// Returns higher than this above their bin's lowest return cannot be inliers of (or lie
// under) a plausible plane of that bin; they are left out of scoring.
constexpr float kCandidateBand_m = 1.0f;
// A segment plane needs eq. 3 inliers from at least this many rings.
constexpr int kMinGroundRings = 3;
// Near a partition line (within this many bins) a return may also be labelled by the
// plane across the line, and planes of adjacent segments need only meet within this
// distance of the line: the cut is quantised to bins and found by score, the terrain break
// is neither.
constexpr float kSoftBoundaryBins = 2.0f;

float signed_height(const Plane& p, float x, float y, float z) {
  return p.nx * x + p.ny * y + p.nz * z + p.d;
}

float plane_z(const Plane& p, float x, float y) { return -(p.nx * x + p.ny * y + p.d) / p.nz; }
float slope_x(const Plane& p) { return -p.nx / p.nz; }
float slope_y(const Plane& p) { return -p.ny / p.nz; }
float plane_gap(const Plane& a, const Plane& b, float x, float y) {
  return std::abs(plane_z(a, x, y) - plane_z(b, x, y));
}

class TangentMethod final : public Method {
 public:
  explicit TangentMethod(const DetectorConfig& c) : cfg_(c) {
    bins_ = c.grid_bins;
    bin_ = static_cast<float>(c.bin_size_m);
    half_ = 0.5f * bin_ * static_cast<float>(bins_);
    radius_ = static_cast<float>(c.fit_radius_m);
    eps_ = static_cast<float>(c.inlier_distance_m);
    sin_delta_ = std::sin(static_cast<float>(c.tangent_angle_deg) * kDegToRad);
    sub_ = c.subsample_cell_m > 0
               ? std::max(1, static_cast<int>(std::ceil(c.bin_size_m / c.subsample_cell_m)))
               : 0;
    origin_x_ = static_cast<float>(c.extrinsics.x_m);
    origin_y_ = static_cast<float>(c.extrinsics.y_m);
    label_up_ = static_cast<float>(c.label_height_m);
    label_down_ = static_cast<float>(c.label_below_m);
    steep_up_ = static_cast<float>(c.steep_label_height_m);
    soft_m_ = kSoftBoundaryBins * bin_;
    grid_.bins = bins_;
    grid_.bin_m = bin_;
    grid_.half_m = half_;
    grid_.origin_x = origin_x_;
    grid_.origin_y = origin_y_;
    grid_.radius_m = radius_;
    grid_.sub = sub_;
    grid_.band_m = kCandidateBand_m;
  }

  void detect(const Frame& frame, const Cloud& cloud, GroundResult& out) override {
    auto t = Clock::now();
    TangentParams tp;
    if (frame.columns() > 0)  // a rotation spans the frame's columns (about 2 pi)
      tp.column_angle_rad = 2.f * static_cast<float>(M_PI) / static_cast<float>(frame.columns());
    compute_tangents(cloud, tp, tangents_);
    measure_ring_slopes(frame, ring_slopes_);
    mark_steep(cloud, steep_);
    out.timings.tangents_ms = ms_since(t);
    binning_.sort(cloud, grid_);
    binning_.select(cloud, grid_, tangents_, steep_, cand_, bin_slot_, low_);
    SamplingParams sp;
    sp.bins = bins_;
    sp.hypotheses = cfg_.hypotheses;
    sp.min_nz = std::cos(static_cast<float>(cfg_.max_tilt_deg) * kDegToRad);
    sp.sin_delta = sin_delta_;
    sp.seed = cfg_.seed;
    sample_hypotheses(low_, sp, planes_);
    out.timings.hypotheses_ms = ms_since(t);
    ScoreParams score_params;
    score_params.eps = eps_;
    score_params.sin_delta = sin_delta_;
    score_params.below = -static_cast<float>(cfg_.below_distance_m);
    score_params.penalty = cfg_.below_penalty;
    scorer_.score(cand_, planes_, score_params, scores_);
    out.timings.inliers_ms = ms_since(t);
    SearchInput in;
    in.bins = bins_;
    in.hypotheses = static_cast<int>(planes_.size());
    in.bin_slot = bin_slot_.data();
    in.slot_scores = scores_.data();
    in.min_segment_score = cfg_.min_segment_inliers;
    in.allow_empty_segments = true;
    in.score_bound =
        static_cast<std::int64_t>(cand_.start.back()) * std::max(1, cfg_.below_penalty);
    SearchResult found;
    if (in.hypotheses > 0) found = search_partition(in, search_scratch_);
    out.timings.search_ms = ms_since(t);
    choose_planes(found, cloud, out);
    label(cloud, out);
    out.timings.labelling_ms = ms_since(t);
  }

 private:
  // Segment s of the found partition; x/y bounds in the vehicle frame.
  void set_bounds(const SearchResult& f, GroundResult& out) const {
    const float x_lo = origin_x_ - half_, y_lo = origin_y_ - half_;
    out.centre_x_m = x_lo + static_cast<float>(f.centre_col) * bin_;
    out.centre_y_m = y_lo + static_cast<float>(f.centre_row) * bin_;
    for (int s = 0; s < 4; ++s) {
      GroundSegment& g = out.segments[idx(s)];
      g.x_min_m = (s & 1) ? out.centre_x_m : x_lo;
      g.x_max_m = (s & 1) ? x_lo + 2 * half_ : out.centre_x_m;
      g.y_min_m = (s & 2) ? out.centre_y_m : y_lo;
      g.y_max_m = (s & 2) ? y_lo + 2 * half_ : out.centre_y_m;
    }
  }

  [[nodiscard]] static int segment_of(const GroundResult& out, float x, float y) {
    return (x >= out.centre_x_m ? 1 : 0) + (y >= out.centre_y_m ? 2 : 0);
  }

  // Least-squares refinement of each segment plane on its full-resolution eq. 3 inliers.
  void refine(const Cloud& cloud, GroundResult& out) {
    refine_pass(cloud, out, eps_, true);
    // Second pass in the label band: obstacle bottoms within epsilon no longer pull on it.
    refine_pass(cloud, out, std::min(eps_, label_up_), false);
  }

  [[nodiscard]] PointFacts facts() const {
    return {&tangents_, steep_.data(), binning_.point_bin().data()};
  }

  [[nodiscard]] static SegmentPlanes segment_planes(const GroundResult& out, bool own_only) {
    SegmentPlanes sp;
    for (int s = 0; s < 4; ++s) {
      sp.plane[s] = out.segments[idx(s)].plane;
      sp.usable[s] = !own_only || out.segments[idx(s)].has_ground;
    }
    sp.cx = out.centre_x_m;
    sp.cy = out.centre_y_m;
    return sp;
  }

  void refine_pass(const Cloud& cloud, GroundResult& out, float band, bool check_rings) {
    find_support(cloud, facts(), segment_planes(out, true), band, sin_delta_, support_);
    PlaneFit fits[4];
    std::uint32_t rings[4] = {0, 0, 0, 0};  // rings contributing inliers, one bit each
    for (Index i = 0; i < cloud.size(); ++i) {
      const int s = support_[i];
      if (s > 3) continue;
      // A twin stands for the last return's cell too: both echoes weigh in.
      fits[s].add(cloud.x[i], cloud.y[i], cloud.z[i], cloud.has_twin(i) ? 2 : 1);
      rings[s] |= 1u << (cloud.ring[i] & 31u);
    }
    const float min_nz = std::cos(static_cast<float>(cfg_.max_tilt_deg) * kDegToRad);
    out.total_inliers = 0;
    for (int s = 0; s < 4; ++s) {
      GroundSegment& g = out.segments[idx(s)];
      if (!g.has_ground) continue;
      // Ground is a surface seen by several rings; a single ring's line on a wall or a car
      // side fits a plane just as well, so such a segment has no ground of its own.
      if (check_rings && std::popcount(rings[s]) < required_rings(g)) {
        g.has_ground = false;
        continue;
      }
      g.inliers = fits[s].count();
      out.total_inliers += g.inliers;
      Plane refined;
      if (fits[s].solve(refined) && refined.nz >= min_nz) g.plane = refined;
    }
  }

  // Ground needs kMinGroundRings rings, or every ring that can reach it when fewer do: a far
  // segment (16-40 m on flat ground) is crossed by two rings only. Never fewer than 2.
  [[nodiscard]] int required_rings(const GroundSegment& g) const {
    float near_m = 0, far_m = 0;
    rect_distances(origin_x_, origin_y_, g.x_min_m, g.x_max_m, g.y_min_m, g.y_max_m, near_m, far_m);
    const int reach =
        rings_reaching(ring_slopes_, sensor_height_over(g.plane), near_m, std::min(far_m, radius_));
    return std::clamp(reach, 2, kMinGroundRings);
  }

  [[nodiscard]] float sensor_height_over(const Plane& p) const {
    return signed_height(p, origin_x_, origin_y_, static_cast<float>(cfg_.extrinsics.z_m));
  }

  // Plausibility (docs/detector.md): the anchor is the best-scoring segment whose plane lies
  // a sensor height under the sensor; a segment whose plane disagrees with the anchor's near
  // the partition centre (where they meet) by more than max_step_m has no ground.
  void check_agreement(const SearchResult& f, GroundResult& out) const {
    int anchor = -1;
    for (int s = 0; s < 4; ++s) {
      const GroundSegment& g = out.segments[idx(s)];
      const double h = sensor_height_over(g.plane);
      if (!g.has_ground || h < cfg_.min_sensor_height_m || h > cfg_.max_sensor_height_m) continue;
      if (anchor < 0 || f.score[idx(s)] > f.score[idx(anchor)]) anchor = s;
    }
    if (anchor < 0) {
      for (GroundSegment& g : out.segments) g.has_ground = false;
      return;
    }
    // The segment under the sensor must itself pass the sensor-height prior.
    GroundSegment& own = out.segments[idx(segment_of(out, origin_x_, origin_y_))];
    const double h_own = sensor_height_over(own.plane);
    if (h_own < cfg_.min_sensor_height_m || h_own > cfg_.max_sensor_height_m)
      own.has_ground = false;
    const Plane& a = out.segments[idx(anchor)].plane;
    for (GroundSegment& g : out.segments) {
      if (!g.has_ground) continue;
      // The planes must come within max_step_m of each other within soft_m_ of the centre:
      // the gap there shrinks by at most soft_m_ times the gradient of their difference.
      const float gap = plane_gap(g.plane, a, out.centre_x_m, out.centre_y_m);
      const float gradient =
          std::hypot(slope_x(g.plane) - slope_x(a), slope_y(g.plane) - slope_y(a));
      if (gap - soft_m_ * gradient > cfg_.max_step_m) g.has_ground = false;
    }
    check_edges(out, anchor);
  }

  // Adjacent segments with their own ground must also agree along their shared edge (at
  // 5, 10, 15 m from the centre, inside the fit radius); otherwise the higher one
  // (never the anchor) loses its ground. A tilted plane through car sides or a facade can
  // meet the anchor at the centre yet rise a metre above the terrain further out.
  void check_edges(GroundResult& out, int anchor) const {
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
        if (std::hypot(x - origin_x_, y - origin_y_) > radius_) break;
        const float diff = plane_z(a.plane, x, y) - plane_z(b.plane, x, y);
        if (std::abs(diff) > std::abs(worst)) worst = diff;
      }
      // Slack across the edge: the terrain break may sit a few metres off the cut line.
      const float across = kDir[k][0] != 0 ? slope_y(a.plane) - slope_y(b.plane)
                                           : slope_x(a.plane) - slope_x(b.plane);
      if (std::abs(worst) - soft_m_ * std::abs(across) <= cfg_.max_step_m) continue;
      // Ground is the lower envelope: the plane riding higher is the implausible one.
      int loser = worst > 0 ? kPairs[k][0] : kPairs[k][1];
      if (loser == anchor) loser = kPairs[k][0] + kPairs[k][1] - loser;
      out.segments[idx(loser)].has_ground = false;
    }
  }

  // Net score (b_m of Algorithm 1: eq. 3 inliers minus the below penalty) of plane p over
  // the scoring candidates of the bins of segment s of the partition.
  [[nodiscard]] std::int64_t segment_fit(const SearchResult& f, int s, const Plane& p) const {
    const int c0 = (s & 1) ? f.centre_col : 0, c1 = (s & 1) ? bins_ : f.centre_col;
    const int r0 = (s & 2) ? f.centre_row : 0, r1 = (s & 2) ? bins_ : f.centre_row;
    const float below = -static_cast<float>(cfg_.below_distance_m);
    std::int64_t sum = 0;
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) {
        const std::int32_t slot = bin_slot_[idx(r * bins_ + c)];
        if (slot < 0) continue;
        const Candidates& q = cand_;
        for (Index k = idx(q.start[idx(slot)]); k < idx(q.start[idx(slot) + 1]); ++k) {
          sum += eq3_inlier(p, q.x[k], q.y[k], q.z[k], q.tx[k], q.ty[k], q.tz[k], eps_, sin_delta_);
          if (signed_height(p, q.x[k], q.y[k], q.z[k]) < below) sum -= cfg_.below_penalty;
        }
      }
    return sum;
  }

  // A segment without ground inherits the plane of the neighbour whose hypothesis explains
  // the segment's own returns best (a far segment beyond a grade change takes the plane of
  // the segment across the cut along the slope, not the larger one across the grade);
  // without such evidence, the best-scoring neighbour's.
  void inherit(const SearchResult& f, GroundResult& out) {
    for (int s = 0; s < 4; ++s) own_[s] = out.segments[idx(s)].has_ground;
    for (int s = 0; s < 4; ++s) {
      if (own_[s]) continue;
      int donor = -1;
      std::int64_t best_fit = 0;
      for (int o : {s ^ 1, s ^ 2, s ^ 3}) {
        if (!own_[o]) continue;
        const std::int64_t fit = segment_fit(f, s, out.segments[idx(o)].plane);
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

  void choose_planes(const SearchResult& f, const Cloud& cloud, GroundResult& out) {
    set_bounds(f, out);
    for (int s = 0; s < 4; ++s) {
      GroundSegment& g = out.segments[idx(s)];
      g.has_ground = f.found && f.plane[idx(s)] >= 0;
      if (g.has_ground) g.plane = planes_.at(idx(f.plane[idx(s)]));
    }
    check_agreement(f, out);
    refine(cloud, out);
    check_agreement(f, out);  // refinement may have tilted a plane out of agreement
    inherit(f, out);
  }

  void label(const Cloud& cloud, GroundResult& out) {
    bool any = false;
    for (bool o : own_) any = any || o;
    if (any) {
      LabelRule rule;
      rule.up = label_up_;
      rule.steep_up = steep_up_;
      rule.down = label_down_;
      rule.growth = static_cast<float>(cfg_.label_growth_per_m);
      rule.radius = radius_;
      rule.sin_label = std::sin(2.0f * static_cast<float>(cfg_.tangent_angle_deg) * kDegToRad);
      rule.soft_m = soft_m_;
      label_points(cloud, facts(), segment_planes(out, false), rule, ground_, height_);
    }
    constexpr auto kGround = static_cast<std::uint8_t>(GroundLabel::ground);
    constexpr auto kObstacle = static_cast<std::uint8_t>(GroundLabel::obstacle);
    for (Index i = 0; i < cloud.size(); ++i) {
      const Index cell = cloud.cell[i];
      const int layer = cloud.layer[i];
      const std::uint8_t label = any && ground_[i] != 0 ? kGround : kObstacle;
      out.label[layer][cell] = label;
      if (any) out.height_m[layer][cell] = height_[i];
      if (cloud.has_twin(i)) {  // the same echo in the last layer
        out.label[1][cell] = label;
        if (any) out.height_m[1][cell] = height_[i];
      }
    }
  }

  DetectorConfig cfg_;
  int bins_ = 0, sub_ = 0;
  float bin_ = 1, half_ = 0, label_up_ = 0, label_down_ = 0, steep_up_ = 0, soft_m_ = 0,
        radius_ = 0, eps_ = 0, sin_delta_ = 0, origin_x_ = 0, origin_y_ = 0;
  Tangents tangents_;
  RingSlopes ring_slopes_{};
  std::vector<std::uint8_t> steep_;
  GridSpec grid_;
  Binning binning_;
  std::vector<std::int32_t> bin_slot_;
  Candidates cand_;
  SlotScorer scorer_;
  LowPoints low_;
  PlaneSet planes_;
  std::vector<std::int32_t> scores_;
  SearchScratch search_scratch_;
  bool own_[4] = {false, false, false, false};
  std::vector<std::uint8_t> support_, ground_;
  std::vector<float> height_;
};

}  // namespace

std::unique_ptr<Method> make_tangent_method(const DetectorConfig& config) {
  return std::make_unique<TangentMethod>(config);
}

}  // namespace vlpground::detail
