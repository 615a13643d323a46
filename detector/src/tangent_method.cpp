// The paper's method ("tangent"): eq. 3 inlier test with ring tangents, RANSAC hypotheses,
// disjoint cross partition found by Algorithm 1 over integral images, plus the
// plausibility additions documented in docs/detector.md.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <optional>

#include "binning.hpp"
#include "column_profile.hpp"
#include "hypotheses.hpp"
#include "labelling.hpp"
#include "method.hpp"
#include "partition_search.hpp"
#include "plane_checks.hpp"
#include "ring_reach.hpp"
#include "scoring.hpp"
#include "steep.hpp"
#include "tangents.hpp"
#include "terrain_cells.hpp"

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
// The terrain refinement looks for the vehicle's ground out to this multiple of the
// distance where the steepest ring meets it.
constexpr float kNearReach = 1.5f;

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
    grid_ = {bins_, bin_, half_, origin_x_, origin_y_, radius_, sub_, kCandidateBand_m};
    score_params_ = {eps_, sin_delta_, -static_cast<float>(c.below_distance_m), c.below_penalty};
    agreement_ = {origin_x_,
                  origin_y_,
                  static_cast<float>(c.extrinsics.z_m),
                  c.min_sensor_height_m,
                  c.max_sensor_height_m,
                  c.max_step_m,
                  soft_m_,
                  radius_};
  }

  void detect(const Frame& frame, const Cloud& cloud, GroundResult& out) override {
    continues_previous_ = continues_previous(frame.meta);
    profiled_ = false;
    auto t = Clock::now();
    ring_facts(frame, cloud);  // Sec. III-A
    out.timings.tangents_ms = ms_since(t);
    hypotheses(cloud);
    out.timings.hypotheses_ms = ms_since(t);
    scorer_.score(cand_, planes_, score_params_, scores_);  // b_m(c, r) of Algorithm 1
    out.timings.inliers_ms = ms_since(t);
    const SearchResult found = search();
    out.timings.search_ms = ms_since(t);
    choose_planes(found, cloud, out);
    label(cloud, out);
    out.timings.labelling_ms = ms_since(t);
    const FrameMeta& m = frame.meta;
    previous_ = PreviousFrame{m.sequence, m.last_time_ns, m.end, m.complete, profiled_};
  }

 private:
  // Whether this frame is a fragment of a rotation going on from the previous frame's end at
  // the cut: consecutive, the previous one a whole rotation that ended at the cut and whose
  // column profiles ran (they keep its returns), no more than kCutGap_ns between them (a
  // capture's last frame, cut straight ahead by the end of the data).
  [[nodiscard]] bool continues_previous(const FrameMeta& m) const {
    return !m.complete && previous_.has_value() && previous_->complete && previous_->profiled &&
           previous_->end == FrameEnd::cut && m.sequence == previous_->sequence + 1 &&
           m.first_time_ns - previous_->last_time_ns <= kCutGap_ns;
  }

  // Tangents, steep flags and ring elevations.
  void ring_facts(const Frame& frame, const Cloud& cloud) {
    TangentParams tp;
    if (frame.columns() > 0)  // a rotation spans the frame's columns (about 2 pi)
      tp.column_angle_rad = 2.f * static_cast<float>(M_PI) / static_cast<float>(frame.columns());
    compute_tangents(cloud, tp, tangents_);
    measure_ring_slopes(frame, ring_slopes_);
    mark_steep(cloud, steep_);
  }

  // Bins, scoring candidates and M sampled planes.
  void hypotheses(const Cloud& cloud) {
    binning_.sort(cloud, grid_);
    binning_.select(cloud, grid_, tangents_, steep_, cand_, bin_slot_, low_);
    SamplingParams sp;
    sp.bins = bins_;
    sp.hypotheses = cfg_.hypotheses;
    sp.min_nz = std::cos(static_cast<float>(cfg_.max_tilt_deg) * kDegToRad);
    sp.sin_delta = sin_delta_;
    sp.seed = cfg_.seed;
    sample_hypotheses(low_, sp, planes_);
  }

  // Algorithm 1 over the slot scores.
  SearchResult search() {
    SearchInput in;
    in.bins = bins_;
    in.hypotheses = static_cast<int>(planes_.size());
    in.bin_slot = bin_slot_.data();
    in.slot_scores = scores_.data();
    in.min_segment_score = cfg_.min_segment_inliers;
    in.allow_empty_segments = true;
    in.score_bound =
        static_cast<std::int64_t>(cand_.start.back()) * std::max(1, cfg_.below_penalty);
    return in.hypotheses > 0 ? search_partition(in, search_scratch_) : SearchResult{};
  }

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
    // Arrays in locals, read once per frame (only a deduplicated cloud has twins).
    const std::uint8_t* const support = support_.data();
    const float *const x = cloud.x.data(), *const y = cloud.y.data(), *const z = cloud.z.data();
    const std::uint16_t* const ring = cloud.ring.data();
    const std::uint8_t* const twin = cloud.deduplicated ? cloud.twin.data() : nullptr;
    const Index n = cloud.size();
    for (Index i = 0; i < n; ++i) {
      const int s = support[i];
      if (s > 3) continue;
      // A twin stands for the last return's cell too: both echoes weigh in.
      fits[s].add(x[i], y[i], z[i], twin != nullptr && twin[i] != 0 ? 2 : 1);
      rings[s] |= 1u << (ring[i] & 31u);
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

  void choose_planes(const SearchResult& f, const Cloud& cloud, GroundResult& out) {
    set_bounds(f, out);
    for (int s = 0; s < 4; ++s) {
      GroundSegment& g = out.segments[idx(s)];
      g.has_ground = f.found && f.plane[idx(s)] >= 0;
      if (g.has_ground) g.plane = planes_.at(idx(f.plane[idx(s)]));
    }
    check_agreement(f, agreement_, out);
    refine(cloud, out);
    check_agreement(f, agreement_, out);  // refinement may have tilted a plane out of agreement
    for (int s = 0; s < 4; ++s) own_[s] = out.segments[idx(s)].has_ground;
    inherit_planes(f, SegmentEvidence{&cand_, bin_slot_.data(), bins_, score_params_}, out);
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
      if (cfg_.terrain_refinement) {
        cells_.fit(cand_, bin_slot_, segment_planes(out, false), cell_params());
        cells_.relabel(cloud, facts(), rule, ground_, height_);
        if (cfg_.column_profiles) follow_columns(cloud, true);
      }
    } else if (profiles_alone()) {
      // No plane at all (a partial rotation, a crowded frame), but the mounting height says
      // where the ground under the vehicle is: the column profiles alone.
      height_.assign(cloud.size(), std::nanf(""));
      ground_.assign(cloud.size(), 0);
      follow_columns(cloud, false);
      any = true;
    }
    write_cells(cloud, any, out);
  }

  // Labels (and with `labelled`, heights) of every return into its cell of the frame, a layer's
  // points at a time (the cloud is in layer order).
  void write_cells(const Cloud& cloud, bool labelled, GroundResult& out) const {
    constexpr auto kGround = static_cast<std::uint8_t>(GroundLabel::ground);
    constexpr auto kObstacle = static_cast<std::uint8_t>(GroundLabel::obstacle);
    const Index layer_begin[3] = {0, strongest_end(cloud), cloud.size()};
    // Arrays held in locals: a label is a byte store, which may alias anything, so members
    // read through `this` would be reloaded at every return.
    const std::uint32_t* const cell = cloud.cell.data();
    const std::uint8_t* const ground = ground_.data();
    const float* const over = height_.data();
    for (Index layer = 0; layer < 2; ++layer) {
      std::uint8_t* const label = out.label[layer].data();
      float* const height = out.height_m[layer].data();
      const Index begin = layer_begin[layer], end = layer_begin[layer + 1];
      if (!labelled) {
        for (Index i = begin; i < end; ++i) label[cell[i]] = kObstacle;
        continue;
      }
      for (Index i = begin; i < end; ++i) {
        label[cell[i]] = ground[i] != 0 ? kGround : kObstacle;
        height[cell[i]] = over[i];
      }
    }
    // Only a deduplicated cloud has twins (a single-return frame's are all 0).
    if (!cloud.deduplicated || cloud.twin.empty()) return;
    // A twin is the same echo in the last layer's cell (no distinct last return is there).
    const std::uint8_t* const twin = cloud.twin.data();
    const std::uint8_t* const first_label = out.label[0].data();
    std::uint8_t* const last_label = out.label[1].data();
    float* const last_height = out.height_m[1].data();
    for (Index i = 0; i < layer_begin[1]; ++i) {
      if (twin[i] == 0) continue;
      last_label[cell[i]] = first_label[cell[i]];
      if (labelled) last_height[cell[i]] = over[i];
    }
  }

  // Without any plane, the column profiles can still start from the mounting height.
  [[nodiscard]] bool profiles_alone() const {
    return cfg_.terrain_refinement && cfg_.column_profiles &&
           mounting_height_known(static_cast<float>(cfg_.extrinsics.z_m),
                                 static_cast<float>(cfg_.min_sensor_height_m));
  }

  // Level 3: column profiles label every return. with_cells: level 2 ran (its surface and
  // the level-1 planes it kept check the profiles).
  void follow_columns(const Cloud& cloud, bool with_cells) {
    profiled_ = true;
    ProfileParams pp;
    pp.sensor_x = origin_x_;
    pp.sensor_y = origin_y_;
    pp.sensor_z = static_cast<float>(cfg_.extrinsics.z_m);
    if (with_cells) pp.vehicle = cells_.vehicle_surface();
    pp.label_up_m = label_up_;
    pp.label_down_m = label_down_;
    pp.steep_band_m = steep_up_;
    pp.continues_previous = continues_previous_;
    // Heights over a level-1 plane that explains its cell (fitting area only).
    plane_height_.resize(cloud.size());
    const float none = std::nanf("");
    if (with_cells) {
      // Without branches: whether a return has a bin is as unpredictable as its cell's fate.
      const std::int32_t* const bin = binning_.point_bin().data();
      const float* const over = height_.data();
      for (Index i = 0; i < cloud.size(); ++i) {
        const bool replaced = cells_.replaced_bin(std::max(bin[i], 0));
        plane_height_[i] = bin[i] >= 0 && !replaced ? over[i] : none;
      }
    } else {
      std::fill(plane_height_.begin(), plane_height_.end(), none);
    }
    const Level2Coverage coverage =
        with_cells ? cells_.coverage(binning_.point_bin().data()) : Level2Coverage{};
    profile_steep_ = steep_;
    add_faces_across_gaps(cloud, face_table_, profile_steep_);
    profiles_.label(cloud, profile_steep_.data(), coverage, plane_height_, pp, ground_, height_);
  }

  [[nodiscard]] CellParams cell_params() const {
    CellParams p;
    p.bins = bins_;
    p.bin_m = bin_;
    p.x_lo = origin_x_ - half_;
    p.y_lo = origin_y_ - half_;
    p.cell_bins =
        std::max(1, static_cast<int>(std::lround(cfg_.refinement_cell_m / cfg_.bin_size_m)));
    p.eps = eps_;
    p.sin_delta = std::sin(2.0f * static_cast<float>(cfg_.tangent_angle_deg) * kDegToRad);
    p.sensor_x = origin_x_;
    p.sensor_y = origin_y_;
    p.sensor_z = static_cast<float>(cfg_.extrinsics.z_m);
    p.min_sensor_height_m = static_cast<float>(cfg_.min_sensor_height_m);
    p.max_sensor_height_m = static_cast<float>(cfg_.max_sensor_height_m);
    p.min_nz = std::cos(static_cast<float>(cfg_.max_tilt_deg) * kDegToRad);
    p.label_up_m = label_up_;
    p.label_down_m = label_down_;
    // Around the vehicle: out to 1.5 x where the steepest ring meets the ground under the
    // mounting height (10 m for a VLP-16 at 1.8 m, 15 m for a Puck Hi-Res), at least 10 m.
    const float steepest = *std::max_element(ring_slopes_.begin(), ring_slopes_.end());
    const float height = std::max(p.sensor_z, 1.8f);
    if (steepest > 0.f) {
      p.blind_m = height / steepest;
      p.near_m = std::max(p.near_m, kNearReach * p.blind_m);
    }
    p.seed = cfg_.seed;
    return p;
  }

  DetectorConfig cfg_;
  int bins_ = 0, sub_ = 0;
  float bin_ = 1, half_ = 0, label_up_ = 0, label_down_ = 0, steep_up_ = 0, soft_m_ = 0,
        radius_ = 0, eps_ = 0, sin_delta_ = 0, origin_x_ = 0, origin_y_ = 0;
  Tangents tangents_;
  RingSlopes ring_slopes_{};
  std::vector<std::uint8_t> steep_;
  std::vector<std::uint8_t> profile_steep_;  // steep_ and faces across gaps (level 3)
  FaceTable face_table_;
  GridSpec grid_;
  ScoreParams score_params_;
  AgreementRules agreement_;
  Binning binning_;
  std::vector<std::int32_t> bin_slot_;
  Candidates cand_;
  SlotScorer scorer_;
  LowPoints low_;
  PlaneSet planes_;
  std::vector<std::int32_t> scores_;
  SearchScratch search_scratch_;
  TerrainCells cells_;
  ColumnProfiles profiles_;
  std::vector<float> plane_height_;
  bool own_[4] = {false, false, false, false};
  // The previous frame detected (continues_previous).
  struct PreviousFrame {
    std::uint64_t sequence;
    std::int64_t last_time_ns;
    FrameEnd end;
    bool complete;
    bool profiled;  // its column profiles ran
  };
  std::optional<PreviousFrame> previous_;
  bool continues_previous_ = false, profiled_ = false;
  // Consecutive frames cut at the same azimuth are a firing (55 us) apart; 1 ms allows for
  // a few lost columns.
  static constexpr std::int64_t kCutGap_ns = 1'000'000;
  std::vector<std::uint8_t> support_, ground_;
  std::vector<float> height_;
};

}  // namespace

std::unique_ptr<Method> make_tangent_method(const DetectorConfig& config) {
  return std::make_unique<TangentMethod>(config);
}

}  // namespace vlpground::detail
