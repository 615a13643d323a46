// Hand-made frames for the evaluation tests: one return per column, with the ground truth
// byte written where the column's provenance says the return came from.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/evaluation/evaluation.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::test {

/// VLP-16 ring -> laser id (rings sorted by elevation; even lasers point down).
inline void set_vlp16_rings(Frame& frame) {
  for (int ring = 0; ring < kLasers; ++ring) {
    frame.laser_of_ring[ring] = static_cast<std::uint8_t>(ring < 8 ? 2 * ring : 2 * (ring - 8) + 1);
  }
}

struct LabelledScene {
  Frame frame{64};
  GroundResult result;
  std::vector<std::uint8_t> truth_bytes = std::vector<std::uint8_t>(8 * 384, 0);
  std::vector<std::int16_t> heights_cm = std::vector<std::int16_t>(8 * 384, 0);

  LabelledScene() {
    set_vlp16_rings(frame);
    for (int l = 0; l < 2; ++l) {
      result.label[l].assign(static_cast<std::size_t>(kLasers * frame.stride()), 0);
      result.height_m[l].assign(static_cast<std::size_t>(kLasers * frame.stride()), NAN);
    }
    result.stride = frame.stride();
  }

  /// Adds a single-return column (ring 0, laser 0) holding one return at (x, y, z) whose truth
  /// is `truth` and whose predicted label is `predicted`. `valid` = false leaves the cell
  /// without a return (the truth byte is still written). `above_cm`: its exact height above
  /// the terrain, seen only through truth_with_heights().
  void add(float x, float y, float z, eval::TruthLabel truth, GroundLabel predicted,
           bool valid = true, std::int16_t above_cm = 0) {
    const int col = frame.append_column();
    const auto c = static_cast<std::size_t>(col);
    frame.column_valid[c] = 1;
    frame.column_packet_index[c] = static_cast<std::uint64_t>(col / 24);
    frame.column_in_packet[c] = static_cast<std::uint8_t>(col % 24);
    const std::size_t cell = frame.index(0, col);
    ReturnLayer& layer = frame.layer[0];
    layer.valid[cell] = valid ? 1 : 0;
    layer.x_m[cell] = x;
    layer.y_m[cell] = y;
    layer.z_m[cell] = z;
    layer.range_m[cell] = std::sqrt(x * x + y * y + z * z);
    result.label[0][cell] = static_cast<std::uint8_t>(valid ? predicted : GroundLabel::no_return);
    const eval::SlotRef slot = eval::slot_of_cell(frame, 0, col, 0);
    const std::size_t at = slot.packet * 384 + static_cast<std::size_t>(slot.slot());
    truth_bytes[at] = static_cast<std::uint8_t>(truth);
    heights_cm[at] = above_cm;
    result.columns = frame.columns();
  }

  [[nodiscard]] eval::GroundTruth truth() const { return eval::GroundTruth(truth_bytes); }
  [[nodiscard]] eval::GroundTruth truth_with_heights() const {
    return eval::GroundTruth(truth_bytes, heights_cm);
  }
};

}  // namespace vlpground::test
