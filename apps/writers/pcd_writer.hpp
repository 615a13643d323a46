// One binary PCD file per frame (fields x y z intensity ring time label, as PCL reads them):
// DIR/frame_000042.pcd. `time` is seconds from the frame's first firing; `label` the
// GroundLabel value (1 ground, 2 obstacle).
//
// Thread-safety: one thread at a time.
#pragma once

#include <string>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::cli {

class PcdWriter {
 public:
  /// Creates `dir` if needed. Throws std::runtime_error.
  explicit PcdWriter(const std::string& dir);
  /// Writes the frame's file; throws std::runtime_error on I/O errors.
  void write(const Frame& frame, const GroundResult& ground);

 private:
  std::string dir_;
  std::vector<char> points_;
};

}  // namespace vlpground::cli
