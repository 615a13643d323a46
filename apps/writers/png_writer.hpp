// One PNG per frame, pictures people can read without the source code:
//   - a header: sensor name, frame number, UTC time of the first firing, rpm, return mode,
//     ground share and detector time;
//   - a bird's-eye view in the vehicle frame (returns moved by the sensor's extrinsics, as
//     the detector sees them; ground green, obstacles red, the partition cross and the four
//     segments' extents, the sensor where it is mounted) with a legend and a scale bar;
//   - the 16 x N range image coloured by label (highest ring on top).
// DIR/frame_000042.png. At finish() (or destruction) DIR/overview.png plots ground share and
// detector time per frame over the run (run_overview.hpp). Buffers are reused between frames.
//
// Thread-safety: one thread at a time.
#pragma once

#include <string>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"
#include "writers/canvas.hpp"
#include "writers/run_overview.hpp"

namespace vlpground::cli {

class PngWriter {
 public:
  static constexpr int kWidth = 800;         // pixels; the view spans +-view_radius_m
  static constexpr int kHeaderPixels = 44;   // two lines of text above the view
  static constexpr int kCaptionPixels = 16;  // between the view and the range image
  static constexpr int kRowPixels = 8;       // height of one ring in the range image

  /// Creates `dir` if needed. `sensor_name` appears in the header (empty: none).
  /// Throws std::runtime_error.
  PngWriter(const std::string& dir, double view_radius_m = 40.0, std::string sensor_name = {},
            const Extrinsics& extrinsics = {});
  ~PngWriter();
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  /// `detect_ms` (< 0: unknown) is printed and plotted in the overview.
  void write(const Frame& frame, const GroundResult& ground, double detect_ms = -1.0);
  /// Writes DIR/overview.png (once; later calls do nothing). Throws std::runtime_error.
  void finish();

 private:
  void draw_header(const Frame& frame, const GroundResult& ground, double detect_ms);
  void draw_birds_eye(const Frame& frame, const GroundResult& ground);
  void draw_partition(const GroundResult& ground);
  void draw_legend();
  void draw_scale_bar();
  void draw_range_image(const Frame& frame, const GroundResult& ground);
  void set_metres(double x_m, double y_m, const Rgb& colour);
  void line_metres(double x0_m, double y0_m, double x1_m, double y1_m, const Rgb& colour);

  std::string dir_;
  std::string sensor_name_;
  double metres_per_pixel_;
  RigidTransform to_vehicle_;
  Canvas canvas_;
  RunOverview overview_;
  bool finished_ = false;
};

}  // namespace vlpground::cli
