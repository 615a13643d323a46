// A small hand-made labelled frame for the PointCloud2 tests: every cell's value encodes its
// position, so a test can tell where each record came from.
#pragma once

#include <cstdint>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::test {

struct LabelledTestFrame {
  Frame frame;
  GroundResult ground;

  LabelledTestFrame(int columns, ReturnMode mode, std::int64_t first_time_ns) : frame(columns) {
    frame.meta.mode = mode;
    frame.meta.first_time_ns = first_time_ns;
    ground.reserve(columns);
    ground.columns = columns;
    for (int r = 0; r < kLasers; ++r) frame.laser_of_ring[r] = static_cast<std::uint8_t>((r * 9) % 16);
    for (int c = 0; c < columns; ++c) {
      frame.append_column();
      frame.column_time_ns[static_cast<std::size_t>(c)] = first_time_ns + c * kSequencePeriodNs;
      for (int l = 0; l < frame.layers(); ++l) {
        for (int r = 0; r < kLasers; ++r) {
          const std::size_t i = frame.index(r, c);
          ReturnLayer& layer = frame.layer[l];
          // Cells where (r + c + l) % 5 == 0 have no return; the others alternate labels.
          const bool valid = (r + c + l) % 5 != 0;
          layer.valid[i] = valid ? 1 : 0;
          layer.x_m[i] = static_cast<float>(c) + 0.25f * static_cast<float>(l);
          layer.y_m[i] = static_cast<float>(r);
          layer.z_m[i] = -1.5f;
          layer.range_m[i] = valid ? 10.f : 0.f;
          layer.intensity[i] = static_cast<std::uint8_t>(r * 10 + l);
          const std::size_t g = static_cast<std::size_t>(r) * static_cast<std::size_t>(ground.stride) +
                                static_cast<std::size_t>(c);
          ground.label[l][g] = static_cast<std::uint8_t>(
              !valid ? GroundLabel::no_return
                     : ((r + c) % 3 == 0 ? GroundLabel::obstacle : GroundLabel::ground));
        }
      }
    }
  }

  [[nodiscard]] std::uint8_t label(int layer, int ring, int col) const {
    return ground.label[layer][static_cast<std::size_t>(ring) *
                                   static_cast<std::size_t>(ground.stride) +
                               static_cast<std::size_t>(col)];
  }
};

}  // namespace vlpground::test
