// Algorithm 1: integral images and the optimised streaming search vs the plain reference.
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "hypotheses.hpp"
#include "partition_search.hpp"

using namespace vlpground::detail;

namespace {

struct Grid {
  int bins, m;
  std::vector<std::int32_t> slot, scores;
  [[nodiscard]] SearchInput input(int t, bool allow_empty) const {
    SearchInput in;
    in.bins = bins;
    in.hypotheses = m;
    in.bin_slot = slot.data();
    in.slot_scores = scores.data();
    in.min_segment_score = t;
    in.allow_empty_segments = allow_empty;
    return in;
  }
};

// Random sparse grid: about 60 % of bins occupied, scores in [-low, 15 - low] (net scores may
// be negative; mostly so with a large `low`), seeded.
Grid random_grid(int bins, int m, std::uint64_t seed, int low = 3) {
  Rng rng(seed);
  Grid g{bins, m, {}, {}};
  for (int b = 0; b < bins * bins; ++b) {
    if (rng.below(10) < 4) {
      g.slot.push_back(-1);
      continue;
    }
    g.slot.push_back(static_cast<std::int32_t>(g.scores.size()) / m);
    for (int k = 0; k < m; ++k) g.scores.push_back(static_cast<std::int32_t>(rng.below(16)) - low);
  }
  return g;
}

// search_partition against reference_search_partition on grid g, both T rules, T in {0, 5,
// 40}, both lane widths (0: unknown bound, 32-bit lanes; else a true bound, 16-bit lanes);
// returns how many comparisons found a centre.
int check_against_reference(const Grid& g, SearchScratch& scratch) {
  int checked = 0;
  for (bool allow_empty : {true, false}) {
    for (int t : {0, 5, 40}) {
      SearchInput in = g.input(t, allow_empty);
      const SearchResult ref = reference_search_partition(in);
      for (std::int64_t bound : {std::int64_t{0}, std::int64_t{12} * g.bins * g.bins}) {
        in.score_bound = bound;
        const SearchResult fast = search_partition(in, scratch);
        INFO("bins " << g.bins << " m " << g.m << " T " << t << " bound " << bound);
        REQUIRE(fast.found == ref.found);
        if (!ref.found) continue;
        ++checked;
        CHECK(fast.centre_col == ref.centre_col);
        CHECK(fast.centre_row == ref.centre_row);
        CHECK(fast.plane == ref.plane);
        CHECK(fast.score == ref.score);
        CHECK(fast.total == ref.total);
      }
    }
  }
  return checked;
}

}  // namespace

TEST_CASE("integral image rectangle sums equal brute-force sums", "[detector][integral]") {
  const Grid g = random_grid(9, 3, 7);
  const SearchInput in = g.input(0, true);
  for (int m = 0; m < 3; ++m) {
    const auto integral = integral_image(in, m);
    for (int c0 = 0; c0 <= 9; c0 += 2)
      for (int r0 = 0; r0 <= 9; r0 += 3)
        for (int c1 = c0; c1 <= 9; c1 += 2)
          for (int r1 = r0; r1 <= 9; r1 += 3) {
            std::int64_t brute = 0;
            for (int r = r0; r < r1; ++r)
              for (int c = c0; c < c1; ++c) {
                const auto s = g.slot[static_cast<std::size_t>(r * 9 + c)];
                if (s >= 0) brute += g.scores[static_cast<std::size_t>(s * 3 + m)];
              }
            REQUIRE(rect_sum(integral, 9, c0, r0, c1, r1) == brute);
          }
  }
}

TEST_CASE("optimised partition search equals the reference Algorithm 1", "[detector][search]") {
  SearchScratch scratch;
  int checked = 0;
  // Seeds 13-20: M past one or more vectors of hypotheses, not a whole number of them (the
  // search pads M to whole vectors when T >= 1); from seed 17 on, scores mostly negative, so
  // that a segment's best is often under 0 (where padding would change T = 0's decisions).
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const int bins = 3 + static_cast<int>(seed % 6);
    const int m =
        seed <= 12 ? 1 + static_cast<int>((seed * 7) % 13) : 9 * static_cast<int>(seed) - 80;
    const Grid g = random_grid(bins, m, seed, seed <= 16 ? 3 : 12);
    INFO("seed " << seed);
    checked += check_against_reference(g, scratch);
  }
  CHECK(checked > 60);
}

TEST_CASE("search finds a planted two-plane partition", "[detector][search]") {
  // Hypothesis 0 explains columns < 4, hypothesis 1 columns >= 4: the best centre cuts at
  // column 4 and assigns 0 to the left segments and 1 to the right ones.
  const int bins = 8, m = 3;
  Grid g{bins, m, {}, {}};
  for (int r = 0; r < bins; ++r)
    for (int c = 0; c < bins; ++c) {
      g.slot.push_back(r * bins + c);
      g.scores.insert(g.scores.end(), {c < 4 ? 5 : 0, c < 4 ? 0 : 5, 1});
    }
  SearchScratch scratch;
  const SearchResult r = search_partition(g.input(1, true), scratch);
  REQUIRE(r.found);
  CHECK(r.centre_col == 4);
  CHECK(r.total == 5 * bins * bins);
  // Rows above/below the cut: whichever row cut won, left segments use 0, right use 1.
  if (r.centre_row > 0) {
    CHECK(r.plane[0] == 0);
    CHECK(r.plane[1] == 1);
  }
  CHECK(r.plane[2] == 0);
  CHECK(r.plane[3] == 1);
}

TEST_CASE("partition search skipping rows under an empty row equals the reference",
          "[detector][search]") {
  // Runs of empty rows at the top, inside and at the bottom (a scene narrower than the
  // grid): the centres under an empty row repeat the ones above it and are not visited.
  SearchScratch scratch;
  int checked = 0, empty_rows = 0;
  for (std::uint64_t seed = 21; seed <= 32; ++seed) {
    const int bins = 6 + static_cast<int>(seed % 5);
    const int m = 5 + static_cast<int>((seed * 7) % 30);
    Grid g = random_grid(bins, m, seed, seed % 2 == 0 ? 3 : 12);
    for (int r = 0; r < bins; ++r) {
      if (!(r < 2 || r == bins / 2 || r + 2 >= bins || (seed % 3 == 0 && r == 3))) continue;
      ++empty_rows;
      for (int c = 0; c < bins; ++c) g.slot[static_cast<std::size_t>(r * bins + c)] = -1;
    }
    INFO("seed " << seed);
    checked += check_against_reference(g, scratch);
  }
  CHECK(empty_rows > 60);
  CHECK(checked > 60);
}
