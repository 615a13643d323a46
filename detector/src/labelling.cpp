#include "labelling.hpp"

#include <algorithm>
#include <cmath>

#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

struct Lanes {
  const float *x, *y, *z, *range, *tx, *ty, *tz;
  const std::uint8_t *valid, *steep;
  const std::int32_t* bin;
};

Lanes lanes_of(const Cloud& c, const PointFacts& f) {
  const Tangents& t = *f.tangents;
  return {c.x.data(), c.y.data(), c.z.data(),     c.range_xy.data(), t.x.data(),
          t.y.data(), t.z.data(), t.valid.data(), f.steep,           f.bin};
}

// One of four values chosen per lane by segment index s, as selects (vectorisable).
template <class T>
inline T pick(T v0, T v1, T v2, T v3, int s) {
  const T lo = (s & 1) != 0 ? v1 : v0, hi = (s & 1) != 0 ? v3 : v2;
  return (s & 2) != 0 ? hi : lo;
}

// The plane of segment s, chosen per lane.
struct PlanePick {
  float nx, ny, nz, d;
  PlanePick(const SegmentPlanes& sp, int s)
      : nx(pick(sp.plane[0].nx, sp.plane[1].nx, sp.plane[2].nx, sp.plane[3].nx, s)),
        ny(pick(sp.plane[0].ny, sp.plane[1].ny, sp.plane[2].ny, sp.plane[3].ny, s)),
        nz(pick(sp.plane[0].nz, sp.plane[1].nz, sp.plane[2].nz, sp.plane[3].nz, s)),
        d(pick(sp.plane[0].d, sp.plane[1].d, sp.plane[2].d, sp.plane[3].d, s)) {}
};

inline int segment_at(float x, float y, float cx, float cy) {
  return static_cast<int>(x >= cx) + 2 * static_cast<int>(y >= cy);
}

// |v| as one bitwise and (v < 0 ? -v : v differs on -0 only, which compares the same).
inline float absolute(float v) { return std::fabs(v); }

// Bitwise & on bools throughout: no short circuit, so no branch in the loops.
VLPGROUND_VECTOR_CLONES
void support_kernel(const Lanes in, Index n, const SegmentPlanes& sp, float band, float sin_delta,
                    std::uint8_t* __restrict out) {
  for (Index i = 0; i < n; ++i) {
    const int s = segment_at(in.x[i], in.y[i], sp.cx, sp.cy);
    const PlanePick p(sp, s);
    // Eq. 3, as eq3_inlier computes it.
    const float dist = p.nx * in.x[i] + p.ny * in.y[i] + p.nz * in.z[i] + p.d;
    const float dot = p.nx * in.tx[i] + p.ny * in.ty[i] + p.nz * in.tz[i];
    const bool inlier = (absolute(dist) < band) & (absolute(dot) < sin_delta);
    const bool eligible = (in.bin[i] >= 0) & (in.valid[i] != 0) & (in.steep[i] == 0);
    out[i] = static_cast<std::uint8_t>(eligible & inlier ? s : 4);
  }
}

// Label rule for one plane (docs/detector.md, "Labels"): height window, grown beyond the fit
// radius, and with a tangent the eq. 3 angle test with twice delta.
inline bool ground_by(float h, float dot, float up, float grow, bool has_tangent,
                      const LabelRule& r) {
  const bool in_window = (h < up + grow) & (h > -r.down - grow);
  return in_window & (!has_tangent | (absolute(dot) < r.sin_label));
}

// Own segment's plane only; returns left obstacle near a partition line are revisited by
// label_near_lines.
// Height window of return i: lower on a steep surface, grown beyond the fit radius.
inline float up_limit(const Lanes& in, Index i, const LabelRule& r) {
  return in.steep[i] != 0 ? std::min(r.up, r.steep_up) : r.up;
}
inline float grow_at(const Lanes& in, Index i, const LabelRule& r) {
  const float range_out = in.range[i] - r.radius;
  return r.growth * (range_out > 0.f ? range_out : 0.f);
}

// Marks a return its own plane refused within soft_m of a partition line, for
// label_near_lines (a label is 0 or 1 once that has run).
constexpr std::uint8_t kNearLine = 2;

inline bool near_line(float v, float line, const LabelRule& r) {
  return absolute(v - line) < r.soft_m;
}

VLPGROUND_VECTOR_CLONES
void label_kernel(const Lanes in, Index n, const SegmentPlanes& sp, const LabelRule r,
                  std::uint8_t* __restrict ground_out, float* __restrict height_out) {
  for (Index i = 0; i < n; ++i) {
    const float x = in.x[i], y = in.y[i], z = in.z[i];
    const PlanePick p(sp, segment_at(x, y, sp.cx, sp.cy));
    const float h = p.nx * x + p.ny * y + p.nz * z + p.d;
    const float dot = p.nx * in.tx[i] + p.ny * in.ty[i] + p.nz * in.tz[i];
    const bool ground =
        ground_by(h, dot, up_limit(in, i, r), grow_at(in, i, r), in.valid[i] != 0, r);
    const bool near = near_line(x, sp.cx, r) | near_line(y, sp.cy, r);
    ground_out[i] = static_cast<std::uint8_t>(ground ? 1 : near ? kNearLine : 0);
    height_out[i] = h;
  }
}

// Near a partition line the planes across it may accept a return its own plane refused
// (marked kNearLine by label_kernel), tried in this order. Planes and rule by value: the byte
// stores of labels would otherwise have the partition centre and the rule reloaded for every
// return.
void label_near_lines(const Lanes in, Index n, const SegmentPlanes sp, const LabelRule r,
                      std::uint8_t* ground, float* height) {
  for (Index i = 0; i < n; ++i) {
    if (ground[i] != kNearLine) continue;
    ground[i] = 0;
    const float x = in.x[i], y = in.y[i], z = in.z[i];
    const bool near_x = near_line(x, sp.cx, r), near_y = near_line(y, sp.cy, r);
    const int own = segment_at(x, y, sp.cx, sp.cy);
    for (int flip = 1; flip < 4; ++flip) {
      if (((flip & 1) != 0 && !near_x) || ((flip & 2) != 0 && !near_y)) continue;
      const PlanePick q(sp, own ^ flip);
      const float hq = q.nx * x + q.ny * y + q.nz * z + q.d;
      const float dot = q.nx * in.tx[i] + q.ny * in.ty[i] + q.nz * in.tz[i];
      if (ground_by(hq, dot, up_limit(in, i, r), grow_at(in, i, r), in.valid[i] != 0, r)) {
        ground[i] = 1;
        height[i] = hq;
        break;
      }
    }
  }
}

}  // namespace

void find_support(const Cloud& cloud, const PointFacts& facts, const SegmentPlanes& planes,
                  float band, float sin_delta, std::vector<std::uint8_t>& support) {
  support.resize(cloud.size());
  // A segment without a usable plane gets one that every return lies far above.
  SegmentPlanes usable = planes;
  for (int s = 0; s < 4; ++s)
    if (!planes.usable[s]) usable.plane[s] = Plane{0.f, 0.f, 1.f, 1e30f};
  support_kernel(lanes_of(cloud, facts), cloud.size(), usable, band, sin_delta, support.data());
}

void label_points(const Cloud& cloud, const PointFacts& facts, const SegmentPlanes& planes,
                  const LabelRule& rule, std::vector<std::uint8_t>& ground,
                  std::vector<float>& height) {
  ground.resize(cloud.size());
  height.resize(cloud.size());
  const Lanes lanes = lanes_of(cloud, facts);
  label_kernel(lanes, cloud.size(), planes, rule, ground.data(), height.data());
  label_near_lines(lanes, cloud.size(), planes, rule, ground.data(), height.data());
}

}  // namespace vlpground::detail
