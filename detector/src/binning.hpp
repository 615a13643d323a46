// The tangent method's horizontal grid: B x B bins around the sensor, the fitting returns
// sorted by bin, and per bin the scoring candidates (sub-sampled) and the low point that
// seeds hypotheses (docs/detector.md, "Scoring").
#pragma once

#include <cstdint>
#include <vector>

#include "hypotheses.hpp"
#include "method.hpp"
#include "scoring.hpp"
#include "tangents.hpp"

namespace vlpground::detail {

struct GridSpec {
  int bins = 80;                         // B; bin (col, row) has index row * B + col
  float bin_m = 1.f;                     // bin side
  float half_m = 40.f;                   // half the grid side: the grid is centred on the origin
  float origin_x = 0.f, origin_y = 0.f;  // sensor position in the vehicle frame
  float radius_m = 40.f;                 // fitting returns: horizontal range within this
  int sub = 10;                          // sub-sampling cells per bin side, 0 = no sub-sampling
  float band_m = 1.f;  // candidates lie within this above their bin's lowest return
};

/// Per-bin selections of one frame. Buffers only grow.
class Binning {
 public:
  /// Counting sort of the fitting returns (within the radius and the square) by bin.
  void sort(const Cloud& cloud, const GridSpec& grid);

  /// Per occupied bin, in bin order: the scoring candidates (the first return of each
  /// sub-sampling cell within the band above the bin's lowest return; a return without a
  /// tangent or on a steep surface keeps t = (0, 0, kNoTangentZ): it only counts as below a
  /// plane) and the lowest candidate with a usable tangent as low point. bin_slot[b] = slot of
  /// bin b, -1 when empty.
  void select(const Cloud& cloud, const GridSpec& grid, const Tangents& tangents,
              const std::vector<std::uint8_t>& steep, Candidates& candidates,
              std::vector<std::int32_t>& bin_slot, LowPoints& low);

  /// Bin of each cloud point, -1 outside the fitting area (after sort).
  [[nodiscard]] const std::vector<std::int32_t>& point_bin() const { return point_bin_; }

 private:
  std::vector<std::int32_t> point_bin_, bin_start_, fill_, sorted_;
  std::vector<std::int32_t> kept_;      // select: the returns of a bin it keeps
  std::vector<std::uint16_t> subcell_;  // sub-sampling cell of each point in its bin
  std::vector<std::uint32_t> stamp_;    // per sub-sampling cell: last bin that used it
  std::uint32_t stamp_value_ = 0;
};

}  // namespace vlpground::detail
