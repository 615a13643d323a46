// Reads a cell's label from a GroundResult (its own stride), tolerating empty results.
#pragma once

#include <cstddef>

#include "vlpground/detector/ground_detector.hpp"

namespace vlpground::cli {

inline GroundLabel label_of(const GroundResult& g, int layer, int ring, int col) {
  const auto& labels = g.label[layer];
  const std::size_t i = static_cast<std::size_t>(ring) * static_cast<std::size_t>(g.stride) +
                        static_cast<std::size_t>(col);
  if (i >= labels.size()) return GroundLabel::no_return;
  return static_cast<GroundLabel>(labels[i]);
}

}  // namespace vlpground::cli
