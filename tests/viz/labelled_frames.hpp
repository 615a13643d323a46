// Labelled frames of a project capture (pcaps/), decoded and detected synchronously, for the
// viz tests. Each has timings {1.5 ms, 2.5 ms} and delivered_index = its position.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vlpground/pipeline.hpp"

namespace vlpground::test {

/// Every frame of `pcaps/<name>` with the default detector.
std::vector<std::unique_ptr<LabelledFrame>> labelled_frames(const std::string& name);

}  // namespace vlpground::test
