// Internal contract between the GroundDetector front end and the methods (tangent, ransac,
// lpr). Not installed.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::detail {

/// Valid returns of a frame in the vehicle frame (extrinsics applied), structure of arrays.
/// Built once per frame by the front end and shared by every method.
struct Cloud {
  std::vector<float> x, y, z;       // vehicle frame, metres
  std::vector<float> range_xy;      // horizontal distance from the sensor origin
  std::vector<std::uint32_t> cell;  // index into the frame's per-cell arrays
  std::vector<std::uint8_t> layer;  // return layer of the point (0 or 1)
  std::vector<std::uint16_t> ring, column;
  [[nodiscard]] std::size_t size() const { return x.size(); }
  void clear();
};

/// Fills `cloud` from every valid cell of every layer of `frame`. No allocation once the
/// vectors have grown to the largest frame seen.
void build_cloud(const Frame& frame, const Extrinsics& extrinsics, Cloud& cloud);

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
