// Algorithm 1 (paper, Sec. III-B): exhaustive cross-partition search with integral images.
#include "partition_search.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <utility>

#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

Index idx(int a) { return static_cast<Index>(a); }

// Segment value under the T rule; false when the centre is disqualified.
bool segment_value(const SearchInput& in, std::int64_t best, std::int64_t& value, bool& ground) {
  ground = best >= in.min_segment_score;
  if (ground) {
    value = best;
    return true;
  }
  value = 0;
  return in.allow_empty_segments;
}

// Applies the decision rule to the four segment maxima of one centre; returns true when
// the centre beats `result` (then `result` holds its totals, planes still to be filled).
bool consider_centre(const SearchInput& in, const std::array<std::int64_t, 4>& maxima, int c, int r,
                     SearchResult& result, std::array<bool, 4>& ground) {
  std::int64_t total = 0;
  std::array<std::int64_t, 4> values{};
  for (int s = 0; s < 4; ++s) {
    if (!segment_value(in, maxima[idx(s)], values[idx(s)], ground[idx(s)])) return false;
    total += values[idx(s)];
  }
  if (result.found && total <= result.total) return false;
  result.found = true;
  result.total = total;
  result.centre_col = c;
  result.centre_row = r;
  result.score = values;
  return true;
}

}  // namespace

namespace {

// The running sums after a pass over the centres of a row: I(c,r) and I(c,B) of the column
// the pass stepped to, I(B,r), I(B,B).
template <class Acc>
struct Sums {
  const Acc *acc, *acc_bottom, *row_total, *total;
  Index m_count;
};

// Columns stepped since a centre: prefix then total of the later one, then of the earlier one
// (nullptr: none).
template <class Acc>
struct Stepped {
  const Acc *p_last, *t_last, *p_first, *t_first;
};

// Rare: a centre beat the best so far. Its planes are the first hypotheses reaching each
// segment's maximum, from its sums: those after the pass less the columns stepped since.
template <class Acc>
void find_planes(const Sums<Acc>& q, const std::array<Acc, 4>& maxima,
                 const std::array<bool, 4>& ground, const Stepped<Acc>& stepped,
                 SearchResult& result) {
  for (int s = 0; s < 4; ++s) {
    result.plane[idx(s)] = -1;
    if (!ground[idx(s)]) continue;
    for (Index m = 0; m < q.m_count; ++m) {
      Acc i = Acc(q.acc[m] - stepped.p_last[m]), ic = Acc(q.acc_bottom[m] - stepped.t_last[m]);
      if (stepped.p_first != nullptr) {
        i = Acc(i - stepped.p_first[m]);
        ic = Acc(ic - stepped.t_first[m]);
      }
      const Acc ib = q.row_total[m];
      const Acc v = s == 0   ? i
                    : s == 1 ? Acc(ib - i)
                    : s == 2 ? Acc(ic - i)
                             : Acc(q.total[m] - ib - ic + i);
      if (v == maxima[idx(s)]) {
        result.plane[idx(s)] = static_cast<int>(m);
        break;
      }
    }
  }
}

// Segment sums of centres (c, r) and (c + 1, r) from I(c,r) (acc), I(B,r), I(c,B)
// (acc_bottom), I(B,B), their maxima, and the steps to columns c + 1 (p0, t0: column c's
// prefix and total) and c + 2 (p1, t1), as one vectorisable pass over M.
template <class Acc>
std::pair<std::array<Acc, 4>, std::array<Acc, 4>> step_two_centres(
    Acc* __restrict acc, Acc* __restrict acc_bottom, const Acc* __restrict row_total,
    const Acc* __restrict total, const Acc* __restrict p0, const Acc* __restrict t0,
    const Acc* __restrict p1, const Acc* __restrict t1, Index m_count) {
  Acc a0 = std::numeric_limits<Acc>::min(), a1 = a0, a2 = a0, a3 = a0;
  Acc n0 = a0, n1 = a0, n2 = a0, n3 = a0;
  for (Index m = 0; m < m_count; ++m) {
    const Acc i = acc[m], ib = row_total[m], ic = acc_bottom[m];
    a0 = std::max(a0, i);
    a1 = std::max(a1, Acc(ib - i));
    a2 = std::max(a2, Acc(ic - i));
    a3 = std::max(a3, Acc(total[m] - ib - ic + i));
    const Acc j = Acc(i + p0[m]), jc = Acc(ic + t0[m]);
    n0 = std::max(n0, j);
    n1 = std::max(n1, Acc(ib - j));
    n2 = std::max(n2, Acc(jc - j));
    n3 = std::max(n3, Acc(total[m] - ib - jc + j));
    acc[m] = Acc(j + p1[m]);
    acc_bottom[m] = Acc(jc + t1[m]);
  }
  return {{a0, a1, a2, a3}, {n0, n1, n2, n3}};
}

// The hypotheses' stride in the search's arrays: M rounded up to a whole number of the
// widest vector build's lanes (AVX-512: 32 16-bit lanes), so that the pass over M
// (step_two_centres) has no scalar remainder; with M = 200 that remainder of 8 took a third
// of the search's time. A padded hypothesis scores 0 in every segment: while T >= 1 that is
// under T, like any segment whose best is under T, which is worth 0 and no ground whatever
// its best, so the padding changes no decision. With T = 0 it would: no padding.
Index hypothesis_stride(const SearchInput& in) {
  constexpr Index kLanes = kWidestVectorBytes / sizeof(std::int16_t);
  const Index m = idx(in.hypotheses);
  return in.min_segment_score >= 1 ? (m + kLanes - 1) / kLanes * kLanes : m;
}

// Acc: int16 when every partial sum fits (twice the lanes per vector), else int32.
template <class Acc>
SearchResult search_streaming(const SearchInput& in, std::vector<Acc>& scratch) {
  const int b = in.bins;
  const Index m_count = idx(in.hypotheses);
  const Index stride = hypothesis_stride(in);
  // Layout: column totals I(c+1,B)-I(c,B) [B x stride], column prefixes over rows < r
  // [B x stride], I(B,B), I(B,r), I(c,r), I(c,B) [stride each]. Prefixes and I(B,r) grow by
  // row r's scores after its centres; the padding past M stays 0.
  scratch.assign(idx(2 * b + 4) * stride, 0);
  Acc* col_total = scratch.data();
  Acc* col_prefix = col_total + idx(b) * stride;
  Acc* total = col_prefix + idx(b) * stride;
  Acc* row_total = total + stride;
  Acc* acc = row_total + stride;
  Acc* acc_bottom = acc + stride;

  for (int r = 0; r < b; ++r) {
    for (int c = 0; c < b; ++c) {
      const std::int32_t slot = in.bin_slot[idx(r * b + c)];
      if (slot < 0) continue;
      const std::int32_t* s = in.slot_scores + idx(slot) * m_count;
      Acc* t = col_total + idx(c) * stride;
      for (Index m = 0; m < m_count; ++m) t[m] = Acc(t[m] + s[m]);
    }
  }
  for (int c = 0; c < b; ++c) {
    const Acc* t = col_total + idx(c) * stride;
    for (Index m = 0; m < stride; ++m) total[m] = Acc(total[m] + t[m]);
  }

  SearchResult result;
  std::array<bool, 4> ground{};
  // Row r - 1 without an occupied bin: every centre of row r has the segment sums of the
  // centre above it, considered before it, which a tie never displaces; the row's centres
  // are skipped (the rows past the scene's extent, about a third of the grid's rows in the
  // shared captures).
  bool previous_row_empty = false;
  for (int r = 0; r < b; ++r) {
    if (!previous_row_empty) {
      std::fill_n(acc, stride, 0);
      std::fill_n(acc_bottom, stride, 0);
      // Two centres per pass over M, (c, r) then (c + 1, r); past the last column (odd B)
      // the second is a phantom stepping over column c again, never considered.
      for (int c = 0; c < b; c += 2) {
        const Index c1 = idx(std::min(c + 1, b - 1));
        const Acc* p0 = col_prefix + idx(c) * stride;
        const Acc* t0 = col_total + idx(c) * stride;
        const Acc* p1 = col_prefix + c1 * stride;
        const Acc* t1 = col_total + c1 * stride;
        const auto [a, n] =
            step_two_centres(acc, acc_bottom, row_total, total, p0, t0, p1, t1, stride);
        const Sums<Acc> sums{acc, acc_bottom, row_total, total, m_count};
        if (consider_centre(in, {a[0], a[1], a[2], a[3]}, c, r, result, ground))
          find_planes(sums, a, ground, {p1, t1, p0, t0}, result);
        if (c + 1 < b && consider_centre(in, {n[0], n[1], n[2], n[3]}, c + 1, r, result, ground))
          find_planes(sums, n, ground, {p1, t1, nullptr, nullptr}, result);
      }
    }
    previous_row_empty = true;
    for (int c = 0; c < b; ++c) {
      const std::int32_t slot = in.bin_slot[idx(r * b + c)];
      if (slot < 0) continue;
      previous_row_empty = false;
      const std::int32_t* s = in.slot_scores + idx(slot) * m_count;
      Acc* p = col_prefix + idx(c) * stride;
      for (Index m = 0; m < m_count; ++m) {
        p[m] = Acc(p[m] + s[m]);
        row_total[m] = Acc(row_total[m] + s[m]);
      }
    }
  }
  return result;
}

}  // namespace

VLPGROUND_VECTOR_CLONES
SearchResult search_partition(const SearchInput& in, SearchScratch& scratch) {
  if (in.score_bound > 0 && in.score_bound <= std::numeric_limits<std::int16_t>::max())
    return search_streaming(in, scratch.narrow);
  return search_streaming(in, scratch.wide);
}

std::vector<std::int64_t> integral_image(const SearchInput& in, int hypothesis) {
  const int b = in.bins;
  const int w = b + 1;
  std::vector<std::int64_t> integral(idx(w * w), 0);
  for (int r = 0; r < b; ++r) {
    for (int c = 0; c < b; ++c) {
      const std::int32_t slot = in.bin_slot[idx(r * b + c)];
      const std::int64_t v =
          slot < 0 ? 0 : in.slot_scores[idx(slot) * idx(in.hypotheses) + idx(hypothesis)];
      integral[idx((r + 1) * w + c + 1)] = v + integral[idx(r * w + c + 1)] +
                                           integral[idx((r + 1) * w + c)] -
                                           integral[idx(r * w + c)];
    }
  }
  return integral;
}

std::int64_t rect_sum(const std::vector<std::int64_t>& integral, int bins, int c0, int r0, int c1,
                      int r1) {
  const int w = bins + 1;
  return integral[idx(r1 * w + c1)] + integral[idx(r0 * w + c0)] - integral[idx(r0 * w + c1)] -
         integral[idx(r1 * w + c0)];
}

SearchResult reference_search_partition(const SearchInput& in) {
  const int b = in.bins;
  std::vector<std::vector<std::int64_t>> integrals;
  for (int m = 0; m < in.hypotheses; ++m) integrals.push_back(integral_image(in, m));
  SearchResult result;
  for (int r = 0; r < b; ++r) {
    for (int c = 0; c < b; ++c) {
      const std::array<std::array<int, 4>, 4> rects{
          {{0, 0, c, r}, {c, 0, b, r}, {0, r, c, b}, {c, r, b, b}}};
      std::array<std::int64_t, 4> maxima{};
      std::array<int, 4> arg{};
      for (int s = 0; s < 4; ++s) {
        const auto& q = rects[idx(s)];
        for (int m = 0; m < in.hypotheses; ++m) {
          const std::int64_t v = rect_sum(integrals[idx(m)], b, q[0], q[1], q[2], q[3]);
          if (m == 0 || v > maxima[idx(s)]) {
            maxima[idx(s)] = v;
            arg[idx(s)] = m;
          }
        }
      }
      std::array<bool, 4> ground{};
      if (consider_centre(in, maxima, c, r, result, ground)) {
        for (int s = 0; s < 4; ++s) result.plane[idx(s)] = ground[idx(s)] ? arg[idx(s)] : -1;
      }
    }
  }
  return result;
}

}  // namespace vlpground::detail
