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

// Hypotheses per block: one vector of float lanes of the build that runs, 16 for AVX-512 and
// 8 for AVX2 (and the baseline). With 8 the AVX-512 build used half of each vector (inliers
// stage 0.27 -> 0.17 ms with 16); with 16 the AVX2 build ran 13-18 % slower (two vectors per
// block, more spills). detector_bench, docs/detector.md "Speed".
constexpr Index kWideBlock = kWidestVectorBytes / sizeof(float);
constexpr Index kNarrowBlock = kAvx2VectorBytes / sizeof(float);

struct Kernel {
  const float *x, *y, *z, *tx, *ty, *tz;
  const std::int32_t* start;
  Index slots;
  const float *nx, *ny, *nz, *d;  // padded to whole blocks
  Index m_count;
};

// Eq. 3 (line 1: |n.x + d| < eps, line 2: |n.t| < sin(delta)) and the below penalty, the
// same float operations as score_reference. Inliers and returns under the plane are counted
// apart and weighed once per block (integers: exact in any order); |v| is fabs, which only
// differs from v < 0 ? -v : v on -0, and compares the same.
template <Index kBlock>
inline void score_blocks(const Kernel q, const ScoreParams p, std::int32_t* __restrict scores) {
  // Block by block over every slot: the block's plane coefficients stay in registers while
  // all the candidates stream past, slot by slot.
  for (Index m0 = 0; m0 < q.m_count; m0 += kBlock) {
    const float* __restrict nx = q.nx + m0;
    const float* __restrict ny = q.ny + m0;
    const float* __restrict nz = q.nz + m0;
    const float* __restrict d = q.d + m0;
    const Index lanes = std::min(kBlock, q.m_count - m0);
    for (Index s = 0; s < q.slots; ++s) {
      const auto begin = static_cast<Index>(q.start[s]), end = static_cast<Index>(q.start[s + 1]);
      std::array<std::int32_t, kBlock> inliers{}, under{};
      for (Index k = begin; k < end; ++k) {
        const float x = q.x[k], y = q.y[k], z = q.z[k], tx = q.tx[k], ty = q.ty[k], tz = q.tz[k];
        for (Index j = 0; j < kBlock; ++j) {
          const float dist = nx[j] * x + ny[j] * y + nz[j] * z + d[j];
          const float dot = nx[j] * tx + ny[j] * ty + nz[j] * tz;
          inliers[j] += (std::fabs(dist) < p.eps) & (std::fabs(dot) < p.sin_delta);
          under[j] += dist < p.below;
        }
      }
      std::int32_t* row = scores + s * q.m_count + m0;
      for (Index j = 0; j < lanes; ++j) row[j] = inliers[j] - p.penalty * under[j];
    }
  }
}

// One build per block size, each cloned per target (`flatten` inlines score_blocks).
VLPGROUND_VECTOR_CLONES
void score_all_narrow(const Kernel q, const ScoreParams p, std::int32_t* __restrict scores) {
  score_blocks<kNarrowBlock>(q, p, scores);
}
VLPGROUND_VECTOR_CLONES
void score_all_wide(const Kernel q, const ScoreParams p, std::int32_t* __restrict scores) {
  score_blocks<kWideBlock>(q, p, scores);
}

}  // namespace

void SlotScorer::score(const Candidates& c, const PlaneSet& planes, const ScoreParams& params,
                       std::vector<std::int32_t>& scores) {
  score_in_blocks(c, planes, params, avx512_clones_run(), scores);
}

void SlotScorer::score_in_blocks(const Candidates& c, const PlaneSet& planes,
                                 const ScoreParams& params, bool wide,
                                 std::vector<std::int32_t>& scores) {
  const Index m_count = planes.size();
  padded_.clear();
  for (Index m = 0; m < m_count; ++m) padded_.push(planes.at(m));
  // A padding plane lies far under every candidate: never an inlier, never above one.
  const Index block = wide ? kWideBlock : kNarrowBlock;
  while (padded_.size() % block != 0) padded_.push(Plane{0.f, 0.f, 1.f, 1e30f});
  scores.resize(c.slots() * m_count);
  if (m_count == 0) return;
  const Kernel q{
      c.x.data(),        c.y.data(),       c.z.data(), c.tx.data(),       c.ty.data(),
      c.tz.data(),       c.start.data(),   c.slots(),  padded_.nx.data(), padded_.ny.data(),
      padded_.nz.data(), padded_.d.data(), m_count};
  if (block == kWideBlock) {
    score_all_wide(q, params, scores.data());
  } else {
    score_all_narrow(q, params, scores.data());
  }
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
