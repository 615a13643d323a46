// Internal contract between the GroundDetector front end and the methods (tangent, ransac,
// lpr). Not installed.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <ranges>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::detail {

/// Valid returns of a frame in the vehicle frame (extrinsics applied), structure of arrays,
/// in (layer, ring, column) order. Built once per frame by the front end.
///
/// With `deduplicated`, a last return that repeats the strongest echo (Frame::same_echo,
/// the same point) is not a point of its own: its strongest twin (twin = 1) stands for both
/// cells. `last_rows` then lists, for every valid last-return cell in (ring, column) order,
/// the point holding its echo (the twin or the distinct last return), so that rows of the
/// last layer can still be walked as the sensor saw them.
struct Cloud {
  std::vector<float> x, y, z;       // vehicle frame, metres
  std::vector<float> range_xy;      // horizontal distance from the sensor origin
  std::vector<std::uint32_t> cell;  // index into the frame's per-cell arrays
  std::vector<std::uint8_t> layer;  // return layer of the point (0 or 1)
  std::vector<std::uint16_t> ring, column;
  std::vector<std::uint8_t> twin;  // empty, or 1 where the last layer repeats the point
  bool deduplicated = false;
  std::size_t last_begin = 0;            // first last-layer point (deduplicated clouds)
  std::vector<std::uint32_t> last_rows;  // deduplicated clouds only
  [[nodiscard]] std::size_t size() const { return x.size(); }
  [[nodiscard]] bool has_twin(std::size_t i) const { return !twin.empty() && twin[i] != 0; }
};

/// Fills `cloud` from every valid cell of every layer of `frame`; with `deduplicate`, dual
/// frames keep one point per distinct echo (see Cloud). No allocation once the vectors have
/// grown to the largest frame seen.
void build_cloud(const Frame& frame, const Extrinsics& extrinsics, bool deduplicate, Cloud& cloud);

/// Runs of a sequence sorted by ring: ring r holds positions [runs[r], runs[r + 1]).
using RingRuns = std::array<std::size_t, kLasers + 1>;

/// Ring runs of positions [first, last), sorted by ring; `ring_at(p)` is position p's ring.
template <class RingAt>
RingRuns ring_runs(std::size_t first, std::size_t last, RingAt ring_at) {
  RingRuns runs{};
  for (int ring = 0; ring <= kLasers; ++ring) {
    const auto positions = std::views::iota(first, last);
    runs[static_cast<std::size_t>(ring)] =
        *std::ranges::partition_point(positions, [&](std::size_t p) { return ring_at(p) < ring; });
  }
  return runs;
}

/// Ring runs of cloud points [first, last) (one layer's points, in cloud order).
RingRuns point_ring_runs(const Cloud& cloud, std::size_t first, std::size_t last);
/// End of the strongest layer's points (the cloud is in layer order).
std::size_t strongest_end(const Cloud& cloud);
/// Ring runs of Cloud::last_rows.
RingRuns last_row_runs(const Cloud& cloud);

/// Position in last_rows of the cell (ring, column), or last_rows.size() when it has no
/// return.
std::size_t last_row_position(const Cloud& cloud, const RingRuns& runs, int ring, int column);

class Method {
 public:
  virtual ~Method() = default;
  /// Writes a label and height for every cell of `frame` into `out` (already sized).
  virtual void detect(const Frame& frame, const Cloud& cloud, GroundResult& out) = 0;
};

std::unique_ptr<Method> make_tangent_method(const DetectorConfig& config);
std::unique_ptr<Method> make_ransac_method(const DetectorConfig& config);
std::unique_ptr<Method> make_lpr_method(const DetectorConfig& config);

}  // namespace vlpground::detail
