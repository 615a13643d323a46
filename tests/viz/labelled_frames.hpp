// Labelled frames of a project capture (pcaps/), decoded and detected synchronously, for the
// viz tests.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vlpground/pipeline.hpp"

namespace vlpground::test {

struct OwnedLabelledFrame {
  std::unique_ptr<Frame> frame;
  std::unique_ptr<GroundResult> ground;
  std::uint64_t index = 0;
  [[nodiscard]] LabelledFrame view() const { return {*frame, *ground, {1.5, 2.5}, index}; }
};

/// Every frame of `pcaps/<name>` with the default detector.
std::vector<OwnedLabelledFrame> labelled_frames(const std::string& name);

}  // namespace vlpground::test
