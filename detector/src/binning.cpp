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
  for (Index i = 0; i < n; ++i)
    if (point_bin_[i] >= 0)
      sorted_[idx(fill_[idx(point_bin_[i])]++)] = static_cast<std::int32_t>(i);
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
  // Candidates are written at slot k, which advances past kept ones only: room for all + 1.
  cand.start.clear();
  for (auto* v : {&cand.x, &cand.y, &cand.z, &cand.tx, &cand.ty, &cand.tz})
    if (v->size() < sorted_.size() + 1) v->resize(sorted_.size() + 1);
  if (cand.ring.size() < sorted_.size() + 1) cand.ring.resize(sorted_.size() + 1);
  stamp_.resize(idx(std::max(1, grid.sub * grid.sub)));
  const std::uint32_t no_sub = grid.sub > 0 ? 0u : 1u;  // without sub-sampling every cell is new
  Index k = 0;
  for (Index b = 0; b < nb; ++b) {
    const Index begin = idx(bin_start_[b]), end = idx(bin_start_[b + 1]);
    if (begin == end) continue;
    float zmin = std::numeric_limits<float>::max();
    for (Index s = begin; s < end; ++s) zmin = std::min(zmin, cloud.z[idx(sorted_[s])]);
    if (++stamp_value_ == 0) std::fill(stamp_.begin(), stamp_.end(), stamp_value_++);
    bin_slot[b] = static_cast<std::int32_t>(cand.start.size());
    cand.start.push_back(static_cast<std::int32_t>(k));
    constexpr Index kNone = std::numeric_limits<Index>::max();
    Index lowest = kNone;
    float z_lowest = std::numeric_limits<float>::infinity();
    for (Index s = begin; s < end; ++s) {
      const Index i = idx(sorted_[s]);
      std::uint32_t& stamp = stamp_[no_sub != 0 ? 0 : subcell_[i]];
      const bool keep =
          (cloud.z[i] <= zmin + grid.band_m) & ((stamp != stamp_value_) | (no_sub != 0));
      stamp = keep ? stamp_value_ : stamp;
      const bool ground_like = (tangents.valid[i] != 0) & (steep[i] == 0);
      cand.x[k] = cloud.x[i];
      cand.y[k] = cloud.y[i];
      cand.z[k] = cloud.z[i];
      cand.ring[k] = static_cast<std::uint8_t>(cloud.ring[i]);
      cand.tx[k] = ground_like ? tangents.x[i] : 0.f;
      cand.ty[k] = ground_like ? tangents.y[i] : 0.f;
      cand.tz[k] = ground_like ? tangents.z[i] : kNoTangentZ;
      const bool lower = keep & ground_like & (cloud.z[i] < z_lowest);
      lowest = lower ? i : lowest;
      z_lowest = lower ? cloud.z[i] : z_lowest;
      k += keep;
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
