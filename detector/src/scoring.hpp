// Per-bin hypothesis scores of the tangent method (b_m(c, r) of Algorithm 1 as a net score).
#pragma once

#include <cstdint>
#include <vector>

#include "hypotheses.hpp"

namespace vlpground::detail {

/// Scoring candidates grouped by occupied bin ("slot"), structure of arrays. Slot s owns
/// [start[s], start[s + 1]). A return without a usable tangent has t = (0, 0, kNoTangentZ).
struct Candidates {
  std::vector<float> x, y, z, tx, ty, tz;
  std::vector<std::uint8_t> ring;  // the return's ring (terrain refinement counts rings)
  std::vector<std::int32_t> start;
  [[nodiscard]] std::size_t slots() const { return start.empty() ? 0 : start.size() - 1; }
  void clear();
};

struct ScoreParams {
  float eps = 0.2f;       // eq. 3 distance
  float sin_delta = 0.f;  // eq. 3 angle, as |n.t| < sin(delta)
  float below = -0.3f;    // signed distance under which a candidate counts against a plane
  std::int32_t penalty = 2;
};

/// scores[s * M + m] = eq. 3 inliers of plane m among the candidates of slot s, minus
/// penalty x candidates more than -below under it. Exactly the per-point scalar rule
/// (`score_reference`), blocked over hypotheses so that a block's plane coefficients and
/// counts stay in vector registers while a slot's candidates stream past.
class SlotScorer {
 public:
  // In blocks of the running build's vector width (16 planes for AVX-512, else 8).
  void score(const Candidates& c, const PlaneSet& planes, const ScoreParams& params,
             std::vector<std::int32_t>& scores);
  // The same in blocks of `wide` ? 16 : 8 planes, whichever build runs (for tests).
  void score_in_blocks(const Candidates& c, const PlaneSet& planes, const ScoreParams& params,
                       bool wide, std::vector<std::int32_t>& scores);

 private:
  PlaneSet padded_;  // planes padded to whole blocks with planes that never score
};

/// Plain per-point, per-plane form of score_slots, for tests.
void score_reference(const Candidates& c, const PlaneSet& planes, const ScoreParams& params,
                     std::vector<std::int32_t>& scores);

}  // namespace vlpground::detail
