#include "binning.hpp"

#include <algorithm>
#include <limits>

#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::detail {

namespace {

using Index = std::size_t;

Index idx(std::int32_t v) { return static_cast<Index>(v); }

// Bin and sub-sampling cell of every point, branchless.
VLPGROUND_VECTOR_CLONES
void locate(const float* __restrict xs, const float* __restrict ys, const float* __restrict range,
            Index n, const GridSpec g, std::int32_t* __restrict bin,
            std::uint16_t* __restrict subcell) {
  const auto bins = static_cast<float>(g.bins), sub = static_cast<float>(g.sub);
  for (Index i = 0; i < n; ++i) {
    const float fx = (xs[i] - g.origin_x + g.half_m) / g.bin_m;
    const float fy = (ys[i] - g.origin_y + g.half_m) / g.bin_m;
    // Clamped before the conversion only so that it is defined; such points are outside.
    const int c = static_cast<int>(std::clamp(fx, 0.f, bins));
    const int r = static_cast<int>(std::clamp(fy, 0.f, bins));
    const bool inside =
        (range[i] <= g.radius_m) & (fx >= 0) & (fy >= 0) & (c < g.bins) & (r < g.bins);
    bin[i] = inside ? r * g.bins + c : -1;
    const float x0 = g.origin_x - g.half_m + static_cast<float>(c) * g.bin_m;
    const float y0 = g.origin_y - g.half_m + static_cast<float>(r) * g.bin_m;
    const float cx = std::clamp((xs[i] - x0) / g.bin_m * sub, -1.f, sub);
    const float cy = std::clamp((ys[i] - y0) / g.bin_m * sub, -1.f, sub);
    const int sx = std::max(0, std::min(g.sub - 1, static_cast<int>(cx)));
    const int sy = std::max(0, std::min(g.sub - 1, static_cast<int>(cy)));
    subcell[i] = static_cast<std::uint16_t>(sy * g.sub + sx);
  }
}

// The arrays select reads and writes per return, as plain pointers held in locals: a
// uint8_t store (the candidate's ring) may alias any vector's internals, so pointers
// fetched from the vectors would be reloaded after every return.
struct SelectLanes {
  const float *x, *y, *z, *tx, *ty, *tz;
  const std::uint8_t *valid, *steep;
  const std::uint16_t *ring, *subcell;
  const std::int32_t* sorted;
};
struct CandidateLanes {
  float *x, *y, *z, *tx, *ty, *tz;
  std::uint8_t* ring;
};

}  // namespace

void Binning::sort(const Cloud& cloud, const GridSpec& grid) {
  const Index n = cloud.size(), nb = idx(grid.bins * grid.bins);
  point_bin_.resize(n);
  subcell_.resize(n);
  locate(cloud.x.data(), cloud.y.data(), cloud.range_xy.data(), n, grid, point_bin_.data(),
         subcell_.data());
  bin_start_.assign(nb + 1, 0);
  for (Index i = 0; i < n; ++i)
    if (point_bin_[i] >= 0) ++bin_start_[idx(point_bin_[i]) + 1];
  for (Index b = 0; b < nb; ++b) bin_start_[b + 1] += bin_start_[b];
  sorted_.resize(idx(bin_start_[nb]));
  fill_.assign(bin_start_.begin(), bin_start_.end() - 1);
  // Plain pointers in locals: the stores would otherwise have the vectors' pointers reloaded.
  const std::int32_t* const bin = point_bin_.data();
  std::int32_t* const fill = fill_.data();
  std::int32_t* const sorted = sorted_.data();
  for (Index i = 0; i < n; ++i)
    if (bin[i] >= 0) sorted[idx(fill[idx(bin[i])]++)] = static_cast<std::int32_t>(i);
}

void Binning::select(const Cloud& cloud, const GridSpec& grid, const Tangents& tangents,
                     const std::vector<std::uint8_t>& steep, Candidates& cand,
                     std::vector<std::int32_t>& bin_slot, LowPoints& low) {
  const Index nb = idx(grid.bins * grid.bins);
  bin_slot.assign(nb, -1);
  low.slot_of_bin.assign(nb, -1);
  for (auto* v : {&low.x, &low.y, &low.z, &low.tx, &low.ty, &low.tz}) v->clear();
  low.col.clear();
  low.row.clear();
  // Candidates are the kept returns: room for all of them.
  cand.start.clear();
  for (auto* v : {&cand.x, &cand.y, &cand.z, &cand.tx, &cand.ty, &cand.tz})
    if (v->size() < sorted_.size()) v->resize(sorted_.size());
  if (cand.ring.size() < sorted_.size()) cand.ring.resize(sorted_.size());
  stamp_.resize(idx(std::max(1, grid.sub * grid.sub)));
  const std::uint32_t no_sub = grid.sub > 0 ? 0u : 1u;  // without sub-sampling every cell is new
  const SelectLanes in{cloud.x.data(),       cloud.y.data(),  cloud.z.data(),   tangents.x.data(),
                       tangents.y.data(),    tangents.z.data(), tangents.valid.data(),
                       steep.data(),         cloud.ring.data(), subcell_.data(), sorted_.data()};
  const CandidateLanes out{cand.x.data(),  cand.y.data(),  cand.z.data(),   cand.tx.data(),
                           cand.ty.data(), cand.tz.data(), cand.ring.data()};
  if (kept_.size() < sorted_.size()) kept_.resize(sorted_.size());
  std::int32_t* const kept = kept_.data();
  std::uint32_t* const stamps = stamp_.data();
  const float band = grid.band_m;
  Index k = 0;
  for (Index b = 0; b < nb; ++b) {
    const Index begin = idx(bin_start_[b]), end = idx(bin_start_[b + 1]);
    if (begin == end) continue;
    float zmin = std::numeric_limits<float>::max();
    for (Index s = begin; s < end; ++s) zmin = std::min(zmin, in.z[idx(in.sorted[s])]);
    if (++stamp_value_ == 0) std::fill(stamp_.begin(), stamp_.end(), stamp_value_++);
    const std::uint32_t value = stamp_value_;
    bin_slot[b] = static_cast<std::int32_t>(cand.start.size());
    cand.start.push_back(static_cast<std::int32_t>(k));
    constexpr Index kNone = std::numeric_limits<Index>::max();
    Index lowest = kNone;
    float z_lowest = std::numeric_limits<float>::infinity();
    // The returns kept (branchless compaction into kept[0, n)), then copied as candidates.
    Index n = 0;
    for (Index s = begin; s < end; ++s) {
      const Index i = idx(in.sorted[s]);
      std::uint32_t& stamp = stamps[in.subcell[i]];  // cell 0 throughout without sub-sampling
      const bool keep = (in.z[i] <= zmin + band) & ((stamp != value) | (no_sub != 0));
      stamp = keep ? value : stamp;
      kept[n] = static_cast<std::int32_t>(i);
      n += keep;
    }
    for (Index j = 0; j < n; ++j, ++k) {
      const Index i = idx(kept[j]);
      const bool ground_like = (in.valid[i] != 0) & (in.steep[i] == 0);
      out.x[k] = in.x[i];
      out.y[k] = in.y[i];
      out.z[k] = in.z[i];
      out.ring[k] = static_cast<std::uint8_t>(in.ring[i]);
      out.tx[k] = ground_like ? in.tx[i] : 0.f;
      out.ty[k] = ground_like ? in.ty[i] : 0.f;
      out.tz[k] = ground_like ? in.tz[i] : kNoTangentZ;
      const bool lower = ground_like & (in.z[i] < z_lowest);
      lowest = lower ? i : lowest;
      z_lowest = lower ? in.z[i] : z_lowest;
    }
    if (lowest == kNone) continue;
    low.slot_of_bin[b] = static_cast<std::int32_t>(low.x.size());
    low.x.push_back(cloud.x[lowest]);
    low.y.push_back(cloud.y[lowest]);
    low.z.push_back(cloud.z[lowest]);
    low.tx.push_back(tangents.x[lowest]);
    low.ty.push_back(tangents.y[lowest]);
    low.tz.push_back(tangents.z[lowest]);
    low.col.push_back(static_cast<std::int32_t>(b % idx(grid.bins)));
    low.row.push_back(static_cast<std::int32_t>(b / idx(grid.bins)));
  }
  cand.start.push_back(static_cast<std::int32_t>(k));
}

}  // namespace vlpground::detail
