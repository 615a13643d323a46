// Every front-end's options in one struct, and the list of sinks built from them
// (frame_sink.hpp says how to add a front-end).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <vector>

#include "frontends/csv_frontend.hpp"
#include "frontends/foxglove_frontend.hpp"
#include "frontends/frame_sink.hpp"
#include "frontends/mcap_frontend.hpp"
#include "frontends/pcd_frontend.hpp"
#include "frontends/png_frontend.hpp"
#include "frontends/ros2_frontend.hpp"

namespace vlpground::cli {

struct OutputOptions {
  CsvOptions csv;
  PcdOptions pcd;
  PngOptions png;
  McapOptions mcap;
  FoxgloveOptions foxglove;
  Ros2Options ros2;
};

void add_output_options(CLI::App& cmd, OutputOptions& o);

/// The outputs of one of several sensors: files get ".NAME" before their extension
/// (returns.csv -> returns.front.csv), folders a NAME subfolder (png/ -> png/front/), ROS 2
/// topics a "/NAME" suffix and the frame id a "_NAME" suffix.
OutputOptions outputs_for_sensor(const OutputOptions& o, const std::string& name);

/// The requested sinks, in option order. Throws std::runtime_error (one line) when one
/// cannot be opened.
std::vector<std::unique_ptr<FrameSink>> make_sinks(const OutputOptions& o,
                                                   const PipelineConfig& config);

}  // namespace vlpground::cli
