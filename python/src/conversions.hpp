// Conversions between Python values (strings, dicts) and the library's typed choices.
#pragma once

#include <pybind11/pybind11.h>

#include <optional>
#include <string>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/types.hpp"

namespace vlpground::python {

namespace py = pybind11;

/// Detector method name ("tangent", "ransac", "lpr").
std::string method_name(const DetectorConfig& config);
/// Throws ValueError naming the valid methods.
void set_method(DetectorConfig& config, const std::string& name);

/// "vlp16" | "hires"; throws ValueError otherwise.
Model parse_model(const std::string& name);
/// "strongest" | "last" | "dual"; throws ValueError otherwise.
ReturnMode parse_mode(const std::string& name);

/// Nested dict {"source": {...}, "decoder": {...}, "assembler": {...}, ...}.
py::dict counters_dict(const CaptureCounters& c);

}  // namespace vlpground::python
