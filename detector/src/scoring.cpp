#include "scoring.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "tangents.hpp"
#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

void Candidates::clear() {
  for (auto* v : {&x, &y, &z, &tx, &ty, &tz}) v->clear();
  ring.clear();
  start.clear();
}

namespace {

using Index = std::size_t;

// Hypotheses per block: one AVX2 vector of 8 lanes.
constexpr Index kBlock = 8;

// Candidates with a tangent, slot s: [start[s], start[s + 1]).
struct Tangential {
  const float *x, *y, *z, *tx, *ty, *tz;
  const std::int32_t* start;
};

// Candidates without one (t = (0, 0, kNoTangentZ)), slot s: [start[s], start[s + 1]).
struct Bare {
  const float *x, *y, *z;
  const std::int32_t* start;
};

struct Kernel {
  Tangential with;
  Bare bare;
  Index slots;
  const float *nx, *ny, *nz, *d;  // padded to whole blocks
  Index m_count;
};

// One block of planes (kBlock lanes from its first) and a slot's counts against them.
struct Block {
  const float* __restrict nx;
  const float* __restrict ny;
  const float* __restrict nz;
  const float* __restrict d;
};
struct Counts {
  std::array<std::int32_t, kBlock> inliers{}, under{};
};

// Eq. 3 (line 1: |n.x + d| < eps, line 2: |n.t| < sin(delta)) and the below penalty, the
// same float operations as score_reference. Inliers and returns under the plane are counted
// apart and weighed once per block (integers: exact in any order); |v| is fabs, which only
// differs from v < 0 ? -v : v on -0, and compares the same. `t` gives candidate k's tangent.
template <class Tangent>
inline void count(const Block& b, const float* x, const float* y, const float* z, Tangent t,
                  Index begin, Index end, const ScoreParams& p, Counts& c) {
  for (Index k = begin; k < end; ++k) {
    const float tx = t.x(k), ty = t.y(k), tz = t.z(k);
#pragma GCC unroll 1  // vectorised over the block's lanes (unrolled, GCC would go over k)
    for (Index j = 0; j < kBlock; ++j) {
      const float dist = b.nx[j] * x[k] + b.ny[j] * y[k] + b.nz[j] * z[k] + b.d[j];
      const float dot = b.nx[j] * tx + b.ny[j] * ty + b.nz[j] * tz;
      c.inliers[j] += (std::fabs(dist) < p.eps) & (std::fabs(dot) < p.sin_delta);
      c.under[j] += dist < p.below;
    }
  }
}

// ... for candidates without a tangent where no plane of the block passes eq. 3's line 2
// with t = (0, 0, kNoTangentZ): none is an inlier, only those under the plane count.
inline void count_under(const Block& b, const Bare& q, Index begin, Index end,
                        const ScoreParams& p, Counts& c) {
  for (Index k = begin; k < end; ++k) {
#pragma GCC unroll 1  // vectorised over the block's lanes (unrolled, GCC would go over k)
    for (Index j = 0; j < kBlock; ++j) {
      const float dist = b.nx[j] * q.x[k] + b.ny[j] * q.y[k] + b.nz[j] * q.z[k] + b.d[j];
      c.under[j] += dist < p.below;
    }
  }
}

struct ArrayTangent {
  const float *tx, *ty, *tz;
  [[nodiscard]] float x(Index k) const { return tx[k]; }
  [[nodiscard]] float y(Index k) const { return ty[k]; }
  [[nodiscard]] float z(Index k) const { return tz[k]; }
};
struct NoTangent {
  [[nodiscard]] static float x(Index) { return 0.f; }
  [[nodiscard]] static float y(Index) { return 0.f; }
  [[nodiscard]] static float z(Index) { return kNoTangentZ; }
};

// Whether any plane of the block passes eq. 3's line 2 with t = (0, 0, kNoTangentZ): only a
// near-vertical one can (|nz| < sin(delta) / kNoTangentZ, 88 degrees for delta = 10).
inline bool bare_may_fit(const Block& b, const ScoreParams& p) {
  bool any = false;
  for (Index j = 0; j < kBlock; ++j) {
    const float dot = b.nx[j] * NoTangent::x(0) + b.ny[j] * NoTangent::y(0) + b.nz[j] * NoTangent::z(0);
    any = any || std::fabs(dot) < p.sin_delta;
  }
  return any;
}

// Block by block over every slot: the block's plane coefficients stay in registers while
// all the candidates stream past, slot by slot.
VLPGROUND_VECTOR_CLONES
void score_all(const Kernel q, const ScoreParams p, std::int32_t* __restrict scores) {
  const ArrayTangent tangent{q.with.tx, q.with.ty, q.with.tz};
  for (Index m0 = 0; m0 < q.m_count; m0 += kBlock) {
    const Block b{q.nx + m0, q.ny + m0, q.nz + m0, q.d + m0};
    const bool bare_may_be_inliers = bare_may_fit(b, p);
    const Index lanes = std::min(kBlock, q.m_count - m0);
    for (Index s = 0; s < q.slots; ++s) {
      Counts c;
      count(b, q.with.x, q.with.y, q.with.z, tangent, static_cast<Index>(q.with.start[s]),
            static_cast<Index>(q.with.start[s + 1]), p, c);
      const auto bare_begin = static_cast<Index>(q.bare.start[s]);
      const auto bare_end = static_cast<Index>(q.bare.start[s + 1]);
      if (bare_may_be_inliers)
        count(b, q.bare.x, q.bare.y, q.bare.z, NoTangent{}, bare_begin, bare_end, p, c);
      else
        count_under(b, q.bare, bare_begin, bare_end, p, c);
      std::int32_t* row = scores + s * q.m_count + m0;
      for (Index j = 0; j < lanes; ++j) row[j] = c.inliers[j] - p.penalty * c.under[j];
    }
  }
}

// Whether a candidate has no tangent: exactly the t that Binning::select gives it.
bool bare(const Candidates& c, Index k) {
  return c.tz[k] == kNoTangentZ && c.tx[k] == 0.f && c.ty[k] == 0.f;
}

}  // namespace

void SlotScorer::split(const Candidates& c) {
  const Index n = c.x.size(), slots = c.slots();
  for (auto* v : {&with_.x, &with_.y, &with_.z, &with_.tx, &with_.ty, &with_.tz, &bare_x_,
                  &bare_y_, &bare_z_})
    v->resize(n);
  with_.start.resize(slots + 1);
  bare_start_.resize(slots + 1);
  // Both groups written at every candidate, kept by advancing one of the two ends (branchless
  // compaction); plain pointers in locals, so that the stores do not reload them.
  float *const wx = with_.x.data(), *const wy = with_.y.data(), *const wz = with_.z.data();
  float *const wtx = with_.tx.data(), *const wty = with_.ty.data(), *const wtz = with_.tz.data();
  float *const bx = bare_x_.data(), *const by = bare_y_.data(), *const bz = bare_z_.data();
  Index w = 0, b = 0;
  for (Index s = 0; s < slots; ++s) {
    with_.start[s] = static_cast<std::int32_t>(w);
    bare_start_[s] = static_cast<std::int32_t>(b);
    for (auto k = static_cast<Index>(c.start[s]); k < static_cast<Index>(c.start[s + 1]); ++k) {
      wx[w] = bx[b] = c.x[k];
      wy[w] = by[b] = c.y[k];
      wz[w] = bz[b] = c.z[k];
      wtx[w] = c.tx[k];
      wty[w] = c.ty[k];
      wtz[w] = c.tz[k];
      const bool without = bare(c, k);
      w += !without;
      b += without;
    }
  }
  with_.start[slots] = static_cast<std::int32_t>(w);
  bare_start_[slots] = static_cast<std::int32_t>(b);
}

void SlotScorer::score(const Candidates& c, const PlaneSet& planes, const ScoreParams& params,
                       std::vector<std::int32_t>& scores) {
  const Index m_count = planes.size();
  padded_.clear();
  for (Index m = 0; m < m_count; ++m) padded_.push(planes.at(m));
  // A padding plane lies far under every candidate: never an inlier, never above one.
  while (padded_.size() % kBlock != 0) padded_.push(Plane{0.f, 0.f, 1.f, 1e30f});
  scores.resize(c.slots() * m_count);
  if (m_count == 0) return;
  split(c);
  const Kernel q{{with_.x.data(), with_.y.data(), with_.z.data(), with_.tx.data(), with_.ty.data(),
                  with_.tz.data(), with_.start.data()},
                 {bare_x_.data(), bare_y_.data(), bare_z_.data(), bare_start_.data()},
                 c.slots(),
                 padded_.nx.data(),
                 padded_.ny.data(),
                 padded_.nz.data(),
                 padded_.d.data(),
                 m_count};
  score_all(q, params, scores.data());
}

void score_reference(const Candidates& c, const PlaneSet& planes, const ScoreParams& params,
                     std::vector<std::int32_t>& scores) {
  const Index m_count = planes.size(), slots = c.slots();
  scores.assign(slots * m_count, 0);
  for (Index s = 0; s < slots; ++s) {
    for (Index k = static_cast<Index>(c.start[s]); k < static_cast<Index>(c.start[s + 1]); ++k) {
      for (Index m = 0; m < m_count; ++m) {
        const Plane p = planes.at(m);
        const bool inlier = eq3_inlier(p, c.x[k], c.y[k], c.z[k], c.tx[k], c.ty[k], c.tz[k],
                                       params.eps, params.sin_delta);
        const bool under = p.nx * c.x[k] + p.ny * c.y[k] + p.nz * c.z[k] + p.d < params.below;
        scores[s * m_count + m] += (inlier ? 1 : 0) - (under ? params.penalty : 0);
      }
    }
  }
}

}  // namespace vlpground::detail
