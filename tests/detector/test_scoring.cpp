// Per-bin hypothesis scores: the blocked kernel against the plain per-point rule.
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "hypotheses.hpp"
#include "scoring.hpp"
#include "tangents.hpp"

using namespace vlpground;
using namespace vlpground::detail;

namespace {

float uniform(Rng& rng, float lo, float hi) {
  return lo + (hi - lo) * static_cast<float>(rng.next() % 100000) / 100000.f;
}

// Candidates near z = -1.8 (some without a tangent) in `slots` slots of varied size, and
// planes within 0.5 m and a few degrees of the ground, so every branch of eq. 3 and of the
// below penalty is taken.
void random_input(std::uint64_t seed, int slots, int planes, Candidates& c, PlaneSet& p) {
  Rng rng(seed);
  c.clear();
  for (int s = 0; s < slots; ++s) {
    c.start.push_back(static_cast<std::int32_t>(c.x.size()));
    const auto count = static_cast<int>(rng.below(40));
    for (int k = 0; k < count; ++k) {
      c.x.push_back(uniform(rng, -20, 20));
      c.y.push_back(uniform(rng, -20, 20));
      c.z.push_back(uniform(rng, -2.4f, -1.0f));
      const bool tangent = rng.below(5) != 0;
      const float tx = uniform(rng, -1, 1), tz = uniform(rng, -0.3f, 0.3f);
      c.tx.push_back(tangent ? tx : 0.f);
      c.ty.push_back(tangent ? std::sqrt(std::max(0.f, 1 - tx * tx - tz * tz)) : 0.f);
      c.tz.push_back(tangent ? tz : kNoTangentZ);
    }
  }
  c.start.push_back(static_cast<std::int32_t>(c.x.size()));
  p.clear();
  for (int m = 0; m < planes; ++m) {
    const float nx = uniform(rng, -0.1f, 0.1f), ny = uniform(rng, -0.1f, 0.1f);
    const float nz = std::sqrt(1 - nx * nx - ny * ny);
    p.push({nx, ny, nz, uniform(rng, 1.3f, 2.3f)});
  }
}

}  // namespace

TEST_CASE("blocked slot scores equal the per-point eq. 3 rule", "[detector][scoring]") {
  ScoreParams params;
  params.eps = 0.2f;
  params.sin_delta = std::sin(10.f * static_cast<float>(M_PI) / 180.f);
  params.below = -0.3f;
  params.penalty = 2;
  SlotScorer scorer;
  std::int64_t positive = 0, negative = 0;  // slot scores of each sign, over every case
  // Plane counts around the block size (partial last block) and one below it.
  for (int planes : {1, 7, 16, 17, 200}) {
    INFO(planes << " planes");
    Candidates c;
    PlaneSet p;
    random_input(static_cast<std::uint64_t>(planes), 60, planes, c, p);
    std::vector<std::int32_t> fast, plain, narrow, wide;
    scorer.score(c, p, params, fast);
    score_reference(c, p, params, plain);
    REQUIRE(fast.size() == plain.size());
    CHECK(fast == plain);
    // Both block sizes, whichever the CPU picks.
    scorer.score_in_blocks(c, p, params, false, narrow);
    scorer.score_in_blocks(c, p, params, true, wide);
    CHECK(narrow == plain);
    CHECK(wide == plain);
    for (std::int32_t v : plain) (v > 0 ? positive : negative) += v;
  }
  CHECK(positive > 0);
  CHECK(negative < 0);
}

TEST_CASE("slot scores equal the per-point rule for planes steep enough that returns without a "
          "tangent pass the angle test",
          "[detector][scoring]") {
  ScoreParams params;
  params.eps = 0.2f;
  params.sin_delta = std::sin(10.f * static_cast<float>(M_PI) / 180.f);
  SlotScorer scorer;
  Candidates c;
  PlaneSet p;
  random_input(3, 60, 17, c, p);
  // Walls through the candidates: |n.(0, 0, kNoTangentZ)| < sin(delta) for most of them.
  Rng rng(4);
  for (std::size_t m = 0; m < p.size(); m += 2) {
    const float nz = uniform(rng, 0.f, 0.04f), nx = std::sqrt(1 - nz * nz);
    p.nx[m] = nx;
    p.ny[m] = 0.f;
    p.nz[m] = nz;
    p.d[m] = uniform(rng, -20, 20);
  }
  std::vector<std::int32_t> fast, plain;
  scorer.score(c, p, params, fast);
  score_reference(c, p, params, plain);
  CHECK(fast == plain);
  std::int64_t inliers = 0;
  for (std::int32_t v : plain) inliers += v > 0 ? v : 0;
  CHECK(inliers > 0);
}
