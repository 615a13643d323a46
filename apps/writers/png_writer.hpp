// One PNG per frame: a bird's-eye view (ground green, obstacles red, the partition centre and
// the four segments' extents drawn) above the 16 x N range image coloured by label.
// DIR/frame_000042.png. The pixel buffer is reused between frames.
//
// Thread-safety: one thread at a time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::cli {

class PngWriter {
 public:
  static constexpr int kWidth = 800;    // pixels; the view spans +-view_radius_m
  static constexpr int kRowPixels = 8;  // height of one ring in the range image

  /// Creates `dir` if needed. Throws std::runtime_error.
  PngWriter(const std::string& dir, double view_radius_m = 40.0);
  void write(const Frame& frame, const GroundResult& ground);

 private:
  void draw_birds_eye(const Frame& frame, const GroundResult& ground);
  void draw_partition(const GroundResult& ground);
  void draw_range_image(const Frame& frame, const GroundResult& ground);
  void set(int x, int y, const std::uint8_t (&rgb)[3]);
  void line(double x0_m, double y0_m, double x1_m, double y1_m, const std::uint8_t (&rgb)[3]);

  std::string dir_;
  double metres_per_pixel_;
  int height_;
  std::vector<std::uint8_t> pixels_;
};

}  // namespace vlpground::cli
