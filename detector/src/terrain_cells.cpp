#include "terrain_cells.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

#include "hypotheses.hpp"
#include "plane_checks.hpp"
#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

Index idx(int v) { return static_cast<Index>(v); }

constexpr float kHistBin_m = 0.05f;          // residual histogram of a cell
constexpr int kCellHist = 64;                // covers window_down + window_up (<= 3.2 m)
constexpr int kModeBins = 6;                 // the densest 0.3 m of a cell's residuals
constexpr int kLayerMinPoints = 4;           // the lowest layer: this many returns in its window
constexpr float kModeShare = 0.f;            // lowest window with min_points (lower envelope)
constexpr int kNearTrials = 48;              // planes sampled from the returns around the sensor
constexpr float kNearMinArea_m2 = 1.f;       // as the paper's hypotheses
constexpr float kMountingTolerance = 0.15f;  // share of the mounting height
constexpr float kLevel1Share = 0.8f;         // level 1 kept under the sensor with this share
constexpr float kRidgeShare = 0.1f;          // gradient ridge: this share of a spread cell's moment
constexpr float kRidgeFloor_m2 = 1.f;        //   plus this (a cell crossed by one ring)
constexpr float kSoftEdge_m = 1.f;
constexpr float kExplainedShare = 0.9f;   // a segment's band holds this share of its low returns
constexpr float kPlausibleBelow_m = 3.f;  // low returns counted from this far under level 1
constexpr float kPlausibleAbove_m = 3.f;  //   to this far over it
constexpr int kCellTrials = 24;           // planes sampled per cell by search_cell
constexpr float kCellMinArea_m2 = 0.5f;
constexpr float kBelow_m = 0.3f;  // as the paper's below penalty (below_distance_m)
constexpr int kBelowPenalty = 2;
constexpr int kSearchRings = 3;
constexpr float kSingleRingOffset_m = 0.25f;  // fit_layer: largest step on a single ring
constexpr float kFewRingsFrom = 2.f;  // beyond this many near_m, two rings (the reach of the rings)
constexpr int kSeedRings = 3;         // rings among the inliers (vehicle_seed, search_cell)
// climbs_object_line: a two-ring fit far out on level ground that climbs a ring line.
constexpr float kLevelReference = 0.03f;     // the reference's gradient under this: level
constexpr float kNearOnReference_m = 0.15f;  // the nearer ring's mean height over it
constexpr float kLineOverNear_m = 0.3f;      // the farther ring over the nearer one
constexpr float kLineBeyond_m = 1.f;         // ... and this much farther out
constexpr float kLineTurn = 0.1f;            // gradient change of the fit from the reference
constexpr float kBorderStep_m = 0.25f;      // largest step to the reference where they meet
constexpr float kLayerBorderStep_m = 0.5f;  // ... for a correction of the reference (fit_layer)

int segment_at(float x, float y, float cx, float cy) {
  return static_cast<int>(x >= cx) + 2 * static_cast<int>(y >= cy);
}

// Unit normal of z = c + gx x + gy y, pointing up.
struct Normal {
  float x, y, z;
  explicit Normal(const HeightPlane& s) {
    const float inv = 1.f / std::sqrt(1.f + s.gx * s.gx + s.gy * s.gy);
    x = -s.gx * inv;
    y = -s.gy * inv;
    z = inv;
  }
};

// Least squares of r = a + b u + c v with a ridge on b and c (u, v from the cell centre).
struct CorrectionFit {
  double n = 0, su = 0, sv = 0, suu = 0, suv = 0, svv = 0, sr = 0, sur = 0, svr = 0;
  void add(double u, double v, double r) {
    n += 1;
    su += u;
    sv += v;
    suu += u * u;
    suv += u * v;
    svv += v * v;
    sr += r;
    sur += u * r;
    svr += v * r;
  }
  bool solve(double ridge, double out[3]) const {
    const double a[3][3] = {{n, su, sv}, {su, suu + ridge, suv}, {sv, suv, svv + ridge}};
    const double rhs[3] = {sr, sur, svr};
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (!(std::fabs(det) > 1e-12)) return false;
    for (int k = 0; k < 3; ++k) {  // Cramer's rule
      double m[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[i][j] = j == k ? rhs[i] : a[i][j];
      out[k] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) /
               det;
    }
    return true;
  }
};

}  // namespace

HeightPlane HeightPlane::from(const Plane& p) {
  const float inv = 1.f / p.nz;
  return {-p.d * inv, -p.nx * inv, -p.ny * inv};
}

int densest_window(const std::uint16_t* hist, int bins, int width, float share, int min_count) {
  if (bins < width) return -1;
  int sum = 0;
  for (int i = 0; i < width; ++i) sum += hist[i];
  int best = sum;
  // Window sums are rolled once to find the maximum (share 0 needs none: min_count alone
  // decides), then once more for the lowest that reaches the share.
  for (int i = 1; share != 0.f && i + width <= bins; ++i) {
    sum += hist[i + width - 1] - hist[i - 1];
    best = std::max(best, sum);
  }
  const float need = std::max(static_cast<float>(min_count), share * static_cast<float>(best));
  sum = 0;
  for (int i = 0; i < width; ++i) sum += hist[i];
  for (int i = 0; i + width <= bins; ++i) {
    if (i > 0) sum += hist[i + width - 1] - hist[i - 1];
    if (static_cast<float>(sum) >= need) return i;
  }
  return -1;
}

int densest_window_reference(const std::uint16_t* hist, int bins, int width, float share,
                             int min_count) {
  auto window = [&](int i) {
    int s = 0;
    for (int k = i; k < i + width; ++k) s += hist[k];
    return s;
  };
  int best = 0;
  for (int i = 0; i + width <= bins; ++i) best = std::max(best, window(i));
  for (int i = 0; i + width <= bins; ++i) {
    const int w = window(i);
    if (w >= min_count && static_cast<float>(w) >= share * static_cast<float>(best)) return i;
  }
  return -1;
}

int TerrainCells::cell_of(float x, float y) const {
  const int col =
      std::clamp(static_cast<int>(std::floor((x - p_.x_lo) / p_.bin_m)), 0, p_.bins - 1);
  const int row =
      std::clamp(static_cast<int>(std::floor((y - p_.y_lo) / p_.bin_m)), 0, p_.bins - 1);
  return cell_of_bin_[idx(row * p_.bins + col)];
}

// Bins [c0, c1) x [r0, r1) of a cell and its centre.
struct TerrainCells::Fit {
  int c0, c1, r0, r1;
  float xc, yc;
  Fit(const CellParams& p, int side, int cell) {
    const int cc = cell % side, cr = cell / side;
    c0 = cc * p.cell_bins;
    c1 = std::min(p.bins, c0 + p.cell_bins);
    r0 = cr * p.cell_bins;
    r1 = std::min(p.bins, r0 + p.cell_bins);
    xc = p.x_lo + 0.5f * static_cast<float>(c0 + c1) * p.bin_m;
    yc = p.y_lo + 0.5f * static_cast<float>(r0 + r1) * p.bin_m;
  }
  // Calls f(candidate index) for every candidate of the cell's bins.
  template <class F>
  void each(const Candidates& cand, const std::vector<std::int32_t>& bin_slot, int bins,
            F&& f) const {
    for (int r = r0; r < r1; ++r) {
      for (int c = c0; c < c1; ++c) {
        const std::int32_t slot = bin_slot[idx(r * bins + c)];
        if (slot < 0) continue;
        const std::int32_t end = cand.start[idx(slot) + 1];
        for (std::int32_t k = cand.start[idx(slot)]; k < end; ++k) f(idx(k));
      }
    }
  }
};

bool TerrainCells::near_vehicle(int cell) const {
  const Fit f(p_, side_, cell);
  const float dx = f.xc - p_.sensor_x, dy = f.yc - p_.sensor_y;
  return dx * dx + dy * dy < p_.blind_m * p_.blind_m;
}

// "Where one plane does not explain a segment": per level-1 segment, the lowest usable
// return of each bin that could be ground (from kPlausibleBelow_m under the plane to
// kPlausibleAbove_m over it; roofs and canopies are higher) and how many of them lie in the
// plane's label band.
void TerrainCells::explained_segments(const Candidates& cand,
                                      const std::vector<std::int32_t>& bin_slot,
                                      const SegmentPlanes& level1) {
  int low[4] = {0, 0, 0, 0}, in_band[4] = {0, 0, 0, 0};
  HeightPlane planes[4];
  float nz[4];
  for (int s = 0; s < 4; ++s) {
    planes[s] = HeightPlane::from(level1.plane[s]);
    nz[s] = Normal(planes[s]).z;
  }
  for (int b = 0; b < p_.bins * p_.bins; ++b) {
    const std::int32_t slot = bin_slot[idx(b)];
    if (slot < 0) continue;
    Index lowest = 0;
    float z_low = std::numeric_limits<float>::infinity();
    for (std::int32_t k = cand.start[idx(slot)]; k < cand.start[idx(slot) + 1]; ++k) {
      const bool lower = cand.tz[idx(k)] != kNoTangentZ && cand.z[idx(k)] < z_low;
      lowest = lower ? idx(k) : lowest;
      z_low = lower ? cand.z[idx(k)] : z_low;
    }
    if (z_low == std::numeric_limits<float>::infinity()) continue;
    const int s = segment_at(cand.x[lowest], cand.y[lowest], level1.cx, level1.cy);
    const float h = (z_low - planes[s].at(cand.x[lowest], cand.y[lowest])) * nz[s];
    if (h < -kPlausibleBelow_m || h > kPlausibleAbove_m) continue;
    ++low[s];
    in_band[s] += (h < p_.label_up_m) & (h > -p_.label_down_m) ? 1 : 0;
  }
  for (int s = 0; s < 4; ++s)
    segment_explained_[s] =
        static_cast<float>(in_band[s]) >= kExplainedShare * static_cast<float>(low[s]);
}

void TerrainCells::count_candidates(const Candidates& cand,
                                    const std::vector<std::int32_t>& bin_slot) {
  cell_candidates_.assign(surface_.size(), 0);
  // Plain pointers in locals: the int stores would otherwise have every vector reloaded.
  const std::int32_t *slot = bin_slot.data(), *cell = cell_of_bin_.data(),
                     *start = cand.start.data();
  std::int32_t* const count = cell_candidates_.data();
  const Index bins = idx(p_.bins * p_.bins);
  for (Index b = 0; b < bins; ++b)
    if (slot[b] >= 0) count[cell[b]] += start[slot[b] + 1] - start[slot[b]];
}

bool TerrainCells::close(int cell, const HeightPlane& a, const HeightPlane& b) const {
  const Fit f(p_, side_, cell);
  const float hx = 0.5f * static_cast<float>(f.c1 - f.c0) * p_.bin_m;
  const float hy = 0.5f * static_cast<float>(f.r1 - f.r0) * p_.bin_m;
  for (int k = 0; k < 4; ++k) {
    const float x = f.xc + ((k & 1) != 0 ? hx : -hx), y = f.yc + ((k & 2) != 0 ? hy : -hy);
    if (std::abs(a.at(x, y) - b.at(x, y)) >= p_.keep_m) return false;
  }
  return true;
}

bool TerrainCells::fit_cell(int cell, const Candidates& cand,
                            const std::vector<std::int32_t>& bin_slot, const HeightPlane& ref,
                            float border_x, float border_y, HeightPlane& out) {
  // Both fits need min_points inliers among the cell's candidates (most cells far out have
  // fewer: they are not walked).
  if (cell_candidates_[idx(cell)] < p_.min_points) return false;
  // Continuous with the reference where the two meet (the border with the cell it came
  // from): a roof, a wall top or a barrier is a step there.
  auto continuous = [&](const HeightPlane& h, float step) {
    return std::abs(h.at(border_x, border_y) - ref.at(border_x, border_y)) <= step;
  };
  return (fit_layer(cell, cand, bin_slot, ref, out) && continuous(out, kLayerBorderStep_m)) ||
         (search_cell(cell, cand, bin_slot, ref, out) && continuous(out, kBorderStep_m));
}

// Where the terrain bends more than a layer around the reference can show (a bank, the
// shoulder of an embankment): the paper's hypothesis search inside the cell. Planes through
// three of its candidates, scored as Algorithm 1 scores a segment (eq. 3 inliers minus the
// below penalty), each within the bend and step allowed from the reference.
bool TerrainCells::search_cell(int cell, const Candidates& cand,
                               const std::vector<std::int32_t>& bin_slot, const HeightPlane& ref,
                               HeightPlane& out) {
  const Fit f(p_, side_, cell);
  const float side_m = static_cast<float>(p_.cell_bins) * p_.bin_m;
  const float reach = 0.5f * side_m * (std::abs(p_.search_gradient_change) * 1.5f);
  cell_pts_.clear();
  cell_pts_.reserve(cand.x.size());
  f.each(cand, bin_slot, p_.bins, [&](Index k) {
    const float r = cand.z[k] - ref.at(cand.x[k], cand.y[k]);
    if (r > -p_.window_down_m - reach && r < p_.window_up_m + reach && cand.tz[k] != kNoTangentZ)
      cell_pts_.push_back(static_cast<std::int32_t>(k));
  });
  if (static_cast<int>(cell_pts_.size()) < p_.min_points) return false;
  auto allowed = [&](const HeightPlane& h) {
    if (std::abs(h.gx - ref.gx) > p_.search_gradient_change ||
        std::abs(h.gy - ref.gy) > p_.search_gradient_change)
      return false;
    if (std::abs(h.gx) > p_.max_gradient || std::abs(h.gy) > p_.max_gradient) return false;
    return true;
  };
  auto net_score = [&](const Plane& pl, PlaneFit* fit, std::uint32_t* rings) {
    int score = 0;
    for (const std::int32_t k : cell_pts_) {
      const Index i = idx(k);
      const float dist = signed_height(pl, cand.x[i], cand.y[i], cand.z[i]);
      if (dist < -kBelow_m) score -= kBelowPenalty;
      if (!eq3_inlier(pl, cand.x[i], cand.y[i], cand.z[i], cand.tx[i], cand.ty[i], cand.tz[i],
                      p_.eps, p_.sin_delta))
        continue;
      ++score;
      if (fit != nullptr) fit->add(cand.x[i], cand.y[i], cand.z[i]);
      if (rings != nullptr) *rings |= 1u << (cand.ring[i] & 31u);
    }
    return score;
  };
  Rng rng(p_.seed * std::uint64_t{0x9E3779B97F4A7C15} + static_cast<std::uint64_t>(cell));
  Plane best{};
  int best_score = p_.min_points - 1;
  for (int trial = 0; trial < kCellTrials; ++trial) {
    float pts[3][3];
    for (auto& pt : pts) {
      const Index i = idx(cell_pts_[rng.below(cell_pts_.size())]);
      pt[0] = cand.x[i];
      pt[1] = cand.y[i];
      pt[2] = cand.z[i];
    }
    Plane h;
    if (!plane_from_points(pts[0], pts[1], pts[2], h, kCellMinArea_m2) ||
        !allowed(HeightPlane::from(h)))
      continue;
    const int score = net_score(h, nullptr, nullptr);
    if (score > best_score) {
      best_score = score;
      best = h;
    }
  }
  if (best_score < p_.min_points) return false;
  PlaneFit fit;
  std::uint32_t rings = 0;
  net_score(best, &fit, &rings);
  // A bend is believed when several rings see it: a ring line on a car or wall is not one.
  const float dx = f.xc - p_.sensor_x, dy = f.yc - p_.sensor_y;
  const bool far = dx * dx + dy * dy > kFewRingsFrom * kFewRingsFrom * p_.near_m * p_.near_m;
  if (std::popcount(rings) < (far ? kSearchRings - 1 : kSearchRings)) return false;
  Plane refined;
  if (fit.solve(refined) && allowed(HeightPlane::from(refined))) best = refined;
  out = HeightPlane::from(best);
  return std::popcount(rings) >= kSearchRings || !climbs_two_ring_line(cand, best, ref, out);
}

// Whether a fit (`best`, as `fit`) of the cell's candidates in cell_pts_ that two rings
// support climbed a ring line on an object (climbs_object_line): its inliers within eps,
// summed up by ring.
bool TerrainCells::climbs_two_ring_line(const Candidates& cand, const Plane& best,
                                        const HeightPlane& ref, const HeightPlane& fit) const {
  constexpr int kRings = 32;
  std::array<float, kRings> count{}, range{}, over{};
  for (const std::int32_t k : cell_pts_) {
    const Index i = idx(k);
    const float dist = signed_height(best, cand.x[i], cand.y[i], cand.z[i]);
    if (std::abs(dist) > p_.eps) continue;
    const Index ring = cand.ring[i] & (kRings - 1u);
    count[ring] += 1.f;
    range[ring] += std::hypot(cand.x[i] - p_.sensor_x, cand.y[i] - p_.sensor_y);
    over[ring] += cand.z[i] - ref.at(cand.x[i], cand.y[i]);
  }
  RingLine nearer{}, farther{};
  bool any = false;
  for (Index ring = 0; ring < kRings; ++ring) {
    if (count[ring] == 0.f) continue;
    const RingLine line{range[ring] / count[ring], over[ring] / count[ring]};
    if (!any || line.range_m < nearer.range_m) nearer = line;
    if (!any || line.range_m > farther.range_m) farther = line;
    any = true;
  }
  return any && climbs_object_line(ref, fit, nearer, farther);
}

bool climbs_object_line(const HeightPlane& reference, const HeightPlane& fit,
                        const RingLine& nearer, const RingLine& farther) {
  return std::hypot(reference.gx, reference.gy) < kLevelReference &&
         std::abs(nearer.over_reference_m) < kNearOnReference_m &&
         farther.over_reference_m - nearer.over_reference_m > kLineOverNear_m &&
         farther.range_m - nearer.range_m > kLineBeyond_m &&
         std::hypot(fit.gx - reference.gx, fit.gy - reference.gy) > kLineTurn;
}

// The cell's candidates with a usable tangent (eq. 3 angle against the reference; no
// tangent: never) into layer_, as offsets from the cell centre and residuals over `ref`:
// the three passes of fit_layer read them, not the whole cell. Plain pointers in locals: the
// ring's byte store would otherwise have every vector's pointer reloaded per candidate.
void TerrainCells::gather_layer(const Fit& f, const Candidates& cand,
                                const std::vector<std::int32_t>& bin_slot,
                                const HeightPlane& ref) {
  LayerPoints& l = layer_;
  if (l.u.size() < cand.x.size()) {  // grows with the largest frame only
    for (auto* v : {&l.u, &l.v, &l.r}) v->resize(cand.x.size());
    l.ring.resize(cand.x.size());
  }
  const float *x = cand.x.data(), *y = cand.y.data(), *z = cand.z.data();
  const float *tx = cand.tx.data(), *ty = cand.ty.data(), *tz = cand.tz.data();
  const std::uint8_t* ring = cand.ring.data();
  float *u = l.u.data(), *v = l.v.data(), *r = l.r.data();
  std::uint8_t* ring_out = l.ring.data();
  const Normal nr(ref);
  const HeightPlane s = ref;
  const float sin_delta = p_.sin_delta, xc = f.xc, yc = f.yc;
  Index n = 0;
  f.each(cand, bin_slot, p_.bins, [&](Index k) {
    if (!(std::abs(nr.x * tx[k] + nr.y * ty[k] + nr.z * tz[k]) < sin_delta)) return;
    u[n] = x[k] - xc;
    v[n] = y[k] - yc;
    r[n] = z[k] - s.at(x[k], y[k]);
    ring_out[n] = ring[k];
    ++n;
  });
  l.n = n;
}

bool TerrainCells::fit_layer(int cell, const Candidates& cand,
                             const std::vector<std::int32_t>& bin_slot, const HeightPlane& ref,
                             HeightPlane& out) {
  const Fit f(p_, side_, cell);
  gather_layer(f, cand, bin_slot, ref);
  const LayerPoints& l = layer_;
  // 1. The lowest dense layer of residuals within the window (lower envelope).
  std::uint16_t hist[kCellHist] = {};
  const int hist_bins =
      std::min(kCellHist, static_cast<int>((p_.window_down_m + p_.window_up_m) / kHistBin_m));
  for (Index j = 0; j < l.n; ++j) {
    const float r = l.r[j] + p_.window_down_m;
    if (r < 0.f) continue;
    const int b = static_cast<int>(r / kHistBin_m);
    if (b < hist_bins) ++hist[b];
  }
  const int first = densest_window(hist, hist_bins, kModeBins, kModeShare, kLayerMinPoints);
  if (first < 0) return false;
  // 2. Two least-squares corrections: around the layer, then around the first fit.
  const float side_m = static_cast<float>(p_.cell_bins) * p_.bin_m;
  double corr[3] = {
      static_cast<double>(-p_.window_down_m +
                          (static_cast<float>(first) + 0.5f * kModeBins) * kHistBin_m),
      0.0, 0.0};
  std::uint32_t rings = 0;
  for (int pass = 0; pass < 2; ++pass) {
    CorrectionFit fit;
    rings = 0;
    for (Index j = 0; j < l.n; ++j) {
      const double u = l.u[j], v = l.v[j], r = l.r[j];
      if (std::fabs(r - (corr[0] + corr[1] * u + corr[2] * v)) < p_.eps) {
        fit.add(u, v, r);
        rings |= 1u << (l.ring[j] & 31u);
      }
    }
    if (fit.n < p_.min_points) return false;
    const double ridge = kRidgeShare * fit.n * side_m * side_m / 12.0 + kRidgeFloor_m2;
    if (!fit.solve(ridge, corr)) return false;
  }
  // 3. Checks scaled with the cell: a bounded step and bend from the reference.
  const float a = static_cast<float>(corr[0]), b = static_cast<float>(corr[1]),
              c = static_cast<float>(corr[2]);
  // One ring's line may lie on a fence or a wall as well as on the ground: it may lower the
  // reference (nothing lies under the ground) but only nudge it up.
  const float offset_limit = p_.offset_m + p_.offset_per_m * side_m;
  const float up_limit = std::popcount(rings) < 2 ? kSingleRingOffset_m : offset_limit;
  if (a > up_limit || a < -offset_limit) return false;
  if (std::abs(b) > p_.gradient_change || std::abs(c) > p_.gradient_change) return false;
  out = {ref.c + a - b * f.xc - c * f.yc, ref.gx + b, ref.gy + c};
  return std::abs(out.gx) <= p_.max_gradient && std::abs(out.gy) <= p_.max_gradient;
}

namespace {

// Score of plane p on the returns around the sensor (gathered in near_pts_): eq. 3 inliers
// less kBelowPenalty per return more than kBelow_m under it. Branchless, vectorised.
VLPGROUND_VECTOR_CLONES
int score_near(const float* __restrict x, const float* __restrict y, const float* __restrict z,
               const float* __restrict tx, const float* __restrict ty,
               const float* __restrict tz, Index n, const Plane p, float eps, float sin_delta) {
  int count = 0;
  for (Index i = 0; i < n; ++i) {
    const float dist = p.nx * x[i] + p.ny * y[i] + p.nz * z[i] + p.d;
    const float dot = p.nx * tx[i] + p.ny * ty[i] + p.nz * tz[i];
    const bool inlier = (std::abs(dist) < eps) & (std::abs(dot) < sin_delta);
    count += static_cast<int>(inlier) - kBelowPenalty * static_cast<int>(dist < -kBelow_m);
  }
  return count;
}

}  // namespace

int TerrainCells::near_score(const Plane& p) const {
  const NearPoints& q = near_pts_;
  return score_near(q.x.data(), q.y.data(), q.z.data(), q.tx.data(), q.ty.data(),
                    q.tz.data(), q.x.size(), p, p_.eps, p_.sin_delta);
}

// Eq. 3 inliers of `p` among the returns around the sensor, into `fit`.
void TerrainCells::fit_near_inliers(const Plane& p, PlaneFit& fit) const {
  const NearPoints& q = near_pts_;
  for (Index i = 0; i < q.x.size(); ++i) {
    if (eq3_inlier(p, q.x[i], q.y[i], q.z[i], q.tx[i], q.ty[i], q.tz[i], p_.eps, p_.sin_delta))
      fit.add(q.x[i], q.y[i], q.z[i]);
  }
}

bool TerrainCells::plausible_under_sensor(const Plane& p) const {
  const float under = p.nx * p_.sensor_x + p.ny * p_.sensor_y + p.nz * p_.sensor_z + p.d;
  return p.nz >= p_.min_nz && under >= p_.min_sensor_height_m && under <= p_.max_sensor_height_m;
}

// With the mounting height known (extrinsics z at least the minimum sensor height), the
// vehicle frame's z = 0 is the ground under the wheels: a plane replacing the level-1 one
// under the sensor must lie near it (roofs of the cars around in a jam do not).
bool TerrainCells::at_mounting_height(const Plane& p) const {
  if (!mounting_height_known(p_.sensor_z, p_.min_sensor_height_m)) return true;
  const float under = p.nx * p_.sensor_x + p.ny * p_.sensor_y + p.nz * p_.sensor_z + p.d;
  return std::abs(under - p_.sensor_z) <= kMountingTolerance * p_.sensor_z;
}

// The ground the vehicle stands on: the level-1 plane when it explains the returns around
// the sensor nearly as well as the best plane sampled from them (the paper's hypothesis
// sampling and eq. 3 count, restricted to near_m), else that plane refined by least squares.
// A lower surface seen beside the vehicle (the fields beside an embankment) cannot win
// here: it explains few of the returns around the vehicle.
HeightPlane TerrainCells::vehicle_seed(const Candidates& cand,
                                       const std::vector<std::int32_t>& bin_slot,
                                       const Plane& level1) {
  near_pts_.clear();  // buffers grow with the largest frame only
  const int reach = static_cast<int>(std::ceil(p_.near_m / p_.bin_m));
  const int sc = std::clamp(static_cast<int>((p_.sensor_x - p_.x_lo) / p_.bin_m), 0, p_.bins - 1);
  const int sr = std::clamp(static_cast<int>((p_.sensor_y - p_.y_lo) / p_.bin_m), 0, p_.bins - 1);
  for (int r = std::max(0, sr - reach); r <= std::min(p_.bins - 1, sr + reach); ++r) {
    for (int c = std::max(0, sc - reach); c <= std::min(p_.bins - 1, sc + reach); ++c) {
      const std::int32_t slot = bin_slot[idx(r * p_.bins + c)];
      if (slot < 0) continue;
      for (std::int32_t k = cand.start[idx(slot)]; k < cand.start[idx(slot) + 1]; ++k) {
        const Index i = idx(k);
        const float dx = cand.x[i] - p_.sensor_x, dy = cand.y[i] - p_.sensor_y;
        if (dx * dx + dy * dy <= p_.near_m * p_.near_m && cand.tz[i] != kNoTangentZ)
          near_pts_.push(cand, i);
      }
    }
  }
  const int own = plausible_under_sensor(level1) ? near_score(level1) : 0;
  const Index near = near_pts_.x.size();
  if (near < 3) return HeightPlane::from(level1);
  Rng rng(p_.seed);
  Plane best{};
  int best_count = -1;
  for (int trial = 0; trial < kNearTrials; ++trial) {
    float pts[3][3];
    for (auto& pt : pts) {
      const Index i = idx(static_cast<std::int32_t>(rng.below(near)));
      pt[0] = near_pts_.x[i];
      pt[1] = near_pts_.y[i];
      pt[2] = near_pts_.z[i];
    }
    Plane h;
    if (!plane_from_points(pts[0], pts[1], pts[2], h, kNearMinArea_m2) ||
        !plausible_under_sensor(h) || !at_mounting_height(h))
      continue;
    const int count = near_score(h);
    if (count > best_count) {
      best_count = count;
      best = h;
    }
  }
  if (best_count < p_.min_points ||
      static_cast<float>(own) >= kLevel1Share * static_cast<float>(best_count))
    return HeightPlane::from(level1);
  for (int pass = 0; pass < 2; ++pass) {  // least squares on the inliers, twice
    PlaneFit fit;
    fit_near_inliers(best, fit);
    Plane refined;
    if (!fit.solve(refined) || !plausible_under_sensor(refined) || !at_mounting_height(refined))
      break;
    best = refined;
  }
  return HeightPlane::from(best);
}

void TerrainCells::fit(const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
                       const SegmentPlanes& level1, const CellParams& params) {
  p_ = params;
  side_ = (p_.bins + p_.cell_bins - 1) / p_.cell_bins;
  if (table_bins_ != p_.bins || table_cell_bins_ != p_.cell_bins) {
    cell_of_bin_.resize(idx(p_.bins * p_.bins));
    for (int row = 0; row < p_.bins; ++row) {
      for (int col = 0; col < p_.bins; ++col) {
        cell_of_bin_[idx(row * p_.bins + col)] = (row / p_.cell_bins) * side_ + col / p_.cell_bins;
      }
    }
    table_bins_ = p_.bins;
    table_cell_bins_ = p_.cell_bins;
  }
  const Index cells = idx(side_ * side_);
  surface_.assign(cells, HeightPlane{});
  state_.assign(cells, CellState::unvisited);
  replace_.assign(cells, 0);
  queue_.resize(cells);
  replaced_ = 0;
  auto level1_at = [&](float x, float y) {
    return HeightPlane::from(level1.plane[segment_at(x, y, level1.cx, level1.cy)]);
  };
  // A cell keeps its level-1 plane (and the paper's labels) where that plane explains the
  // ground: in a segment whose low returns lie in its label band, or where the cell's
  // surface is close to it.
  explained_segments(cand, bin_slot, level1);
  // Every segment explained: no cell can replace its level-1 plane, nothing to grow.
  if (segment_explained_[0] && segment_explained_[1] && segment_explained_[2] &&
      segment_explained_[3]) {
    std::fill(state_.begin(), state_.end(), CellState::level1);
    vehicle_cell_ = idx(cell_of(p_.sensor_x, p_.sensor_y));
    surface_[vehicle_cell_] = level1_at(p_.sensor_x, p_.sensor_y);
    return;
  }
  count_candidates(cand, bin_slot);
  auto settle = [&](int cell, const HeightPlane& s, bool fitted) {
    const Fit f(p_, side_, cell);
    const HeightPlane own = level1_at(f.xc, f.yc);
    const bool keep =
        segment_explained_[segment_at(f.xc, f.yc, level1.cx, level1.cy)] || close(cell, s, own);
    surface_[idx(cell)] = keep ? own : s;
    state_[idx(cell)] = keep     ? CellState::level1
                        : fitted ? CellState::refined
                                 : CellState::inherited;
    replace_[idx(cell)] = keep ? 0 : 1;
    replaced_ += keep ? 0 : 1;
  };
  // Breadth first from the cell under the sensor through the cells whose fit succeeded,
  // each correcting the surface of a fitted neighbour; a failed cell may be retried from
  // another fitted neighbour. Surfaces are never extrapolated through failed cells.
  const int start = cell_of(p_.sensor_x, p_.sensor_y);
  vehicle_cell_ = idx(start);
  const HeightPlane seed = vehicle_seed(
      cand, bin_slot, level1.plane[segment_at(p_.sensor_x, p_.sensor_y, level1.cx, level1.cy)]);
  HeightPlane s;
  settle(start, fit_cell(start, cand, bin_slot, seed, p_.sensor_x, p_.sensor_y, s) ? s : seed,
         true);
  std::size_t head = 0, tail = 0;
  queue_[tail++] = start;
  auto grow = [&] {
    while (head < tail) {
      const int cell = queue_[head++];
      const int cc = cell % side_, cr = cell / side_;
      const int next[4][2] = {{cc + 1, cr}, {cc - 1, cr}, {cc, cr + 1}, {cc, cr - 1}};
      for (const auto& nb : next) {
        if (nb[0] < 0 || nb[1] < 0 || nb[0] >= side_ || nb[1] >= side_) continue;
        const int n = nb[1] * side_ + nb[0];
        if (state_[idx(n)] != CellState::unvisited) continue;
        const HeightPlane ref = surface_[idx(cell)];
        const Fit a(p_, side_, cell), b(p_, side_, n);
        if (fit_cell(n, cand, bin_slot, ref, 0.5f * (a.xc + b.xc), 0.5f * (a.yc + b.yc), s)) {
          settle(n, s, true);
        } else if (near_vehicle(n)) {  // the beams meet the ground only 7-10 m out
          settle(n, ref, true);
        } else {
          continue;
        }
        queue_[tail++] = n;
      }
    }
  };
  grow();
  // Surfaces the vehicle's cannot reach (beyond a shadow or a wall): grown from cells their
  // level-1 plane explains.
  for (int cell = 0; cell < side_ * side_; ++cell) {
    if (state_[idx(cell)] != CellState::unvisited) continue;
    const Fit f(p_, side_, cell);
    const HeightPlane own = level1_at(f.xc, f.yc);
    if (!fit_cell(cell, cand, bin_slot, own, f.xc, f.yc, s)) continue;
    settle(cell, s, true);
    queue_[tail++] = cell;
    grow();
  }
  // Cells without a fit of their own next to fitted ones: the mean of their neighbours'
  // surfaces; the rest keep their level-1 plane.
  for (int cell = 0; cell < side_ * side_; ++cell) {
    if (state_[idx(cell)] != CellState::unvisited) continue;
    const int cc = cell % side_, cr = cell / side_;
    const int next[4][2] = {{cc + 1, cr}, {cc - 1, cr}, {cc, cr + 1}, {cc, cr - 1}};
    HeightPlane mean{0, 0, 0};
    int count = 0;
    for (const auto& nb : next) {
      if (nb[0] < 0 || nb[1] < 0 || nb[0] >= side_ || nb[1] >= side_) continue;
      const Index n = idx(nb[1] * side_ + nb[0]);
      if (!has_own_ground(state_[n])) continue;
      mean.c += surface_[n].c;
      mean.gx += surface_[n].gx;
      mean.gy += surface_[n].gy;
      ++count;
    }
    if (count == 0) {
      const Fit f(p_, side_, cell);
      surface_[idx(cell)] = level1_at(f.xc, f.yc);
      continue;
    }
    const float inv = 1.f / static_cast<float>(count);
    settle(cell, {mean.c * inv, mean.gx * inv, mean.gy * inv}, false);
  }
  normal_.resize(surface_.size());
  for (Index c = 0; c < surface_.size(); ++c) {
    const Normal n(surface_[c]);
    normal_[c] = {n.x, n.y, n.z};
  }
}

void TerrainCells::relabel(const Cloud& cloud, const PointFacts& facts, const LabelRule& rule,
                           std::vector<std::uint8_t>& ground, std::vector<float>& height) const {
  if (replaced_ == 0) return;
  const Tangents& t = *facts.tangents;
  const float cell_m = static_cast<float>(p_.cell_bins) * p_.bin_m;
  auto ground_by = [&](int cell, Index i, float& h) {
    const HeightPlane& s = surface_[idx(cell)];
    const std::array<float, 3>& n = normal_[idx(cell)];
    h = (cloud.z[i] - s.at(cloud.x[i], cloud.y[i])) * n[2];  // distance along the normal
    const float up = facts.steep[i] != 0 ? std::min(rule.up, rule.steep_up) : rule.up;
    const float dot = n[0] * t.x[i] + n[1] * t.y[i] + n[2] * t.z[i];
    return h < up && h > -rule.down && (t.valid[i] == 0 || std::abs(dot) < rule.sin_label);
  };
  // Plain pointers in locals: the byte stores of labels would otherwise have them reloaded
  // for every return, most of which lie in cells that keep their level-1 labels.
  const std::int32_t *const bin_of = facts.bin, *const cell_of = cell_of_bin_.data();
  const std::uint8_t* const replace = replace_.data();
  const Index returns = cloud.size();
  for (Index i = 0; i < returns; ++i) {
    const std::int32_t bin = bin_of[i];
    if (bin < 0) continue;
    const int cell = cell_of[bin];
    if (replace[cell] == 0) continue;
    float h = 0;
    bool is_ground = ground_by(cell, i, h);
    height[i] = h;
    if (!is_ground) {  // near a cell edge the neighbour's surface may accept
      const int cc = cell % side_, cr = cell / side_;
      const float fx = (cloud.x[i] - p_.x_lo) / cell_m - static_cast<float>(cc);
      const float fy = (cloud.y[i] - p_.y_lo) / cell_m - static_cast<float>(cr);
      const float soft = kSoftEdge_m / cell_m;
      const int nx = fx < soft ? cc - 1 : fx > 1.f - soft ? cc + 1 : cc;
      const int ny = fy < soft ? cr - 1 : fy > 1.f - soft ? cr + 1 : cr;
      const bool x_ok = nx != cc && nx >= 0 && nx < side_, y_ok = ny != cr && ny >= 0 && ny < side_;
      for (const int n : {x_ok ? cr * side_ + nx : -1, y_ok ? ny * side_ + cc : -1}) {
        if (n < 0 || state_[idx(n)] == CellState::unvisited) continue;
        float hn = 0;
        if (ground_by(n, i, hn)) {
          is_ground = true;
          height[i] = hn;
          break;
        }
      }
    }
    ground[i] = is_ground ? 1 : 0;
  }
}

}  // namespace vlpground::detail
