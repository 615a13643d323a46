// Cross-partition search of Algorithm 1 over per-bin hypothesis scores.
//
// Bins: B x B, bin (col, row) at index row * B + col. A partition centre (c, r), c, r in
// [0, B), cuts between columns c-1 | c and rows r-1 | r; segments:
//   0: cols [0,c) x rows [0,r)   1: cols [c,B) x rows [0,r)
//   2: cols [0,c) x rows [r,B)   3: cols [c,B) x rows [r,B)
// Each segment takes the hypothesis with the largest summed score (first index on ties);
// the centre with the largest total wins (first in row-major order on ties).
// A segment whose best score is below `min_segment_score` either disqualifies the centre
// (paper: every segment needs T inliers) or, with `allow_empty_segments`, contributes 0
// and has no ground (plane = -1).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace vlpground::detail {

struct SearchInput {
  int bins = 0;                               // B
  int hypotheses = 0;                         // M, stride of `slot_scores`
  const std::int32_t* bin_slot = nullptr;     // B*B entries, -1 = empty bin
  const std::int32_t* slot_scores = nullptr;  // per occupied bin: M scores
  int min_segment_score = 0;                  // T
  bool allow_empty_segments = true;
  // Bound on |sum of scores| over any set of bins (0 = unknown). At most 32767 lets the
  // search run on 16-bit lanes.
  std::int64_t score_bound = 0;
};

struct SearchScratch {
  std::vector<std::int16_t> narrow;
  std::vector<std::int32_t> wide;
};

struct SearchResult {
  bool found = false;
  int centre_col = 0, centre_row = 0;
  std::array<int, 4> plane{-1, -1, -1, -1};  // hypothesis per segment, -1 = no ground
  std::array<std::int64_t, 4> score{};
  std::int64_t total = 0;
};

/// Streaming search: column prefix sums are carried row by row, so the integral image of
/// every hypothesis is evaluated without materialising B x B x M values. Reuses `scratch`.
SearchResult search_partition(const SearchInput& in, SearchScratch& scratch);

/// Plain reference of the same search: one full integral image per hypothesis and the
/// four-corner rectangle sums. Slow; used by tests to check search_partition.
SearchResult reference_search_partition(const SearchInput& in);

/// Integral image (B+1) x (B+1) of one hypothesis: I(c, r) = sum over cols < c, rows < r.
std::vector<std::int64_t> integral_image(const SearchInput& in, int hypothesis);

/// Sum over cols [c0, c1) x rows [r0, r1) from an integral image (paper's h_p(m, s)).
std::int64_t rect_sum(const std::vector<std::int64_t>& integral, int bins, int c0, int r0, int c1,
                      int r1);

}  // namespace vlpground::detail
