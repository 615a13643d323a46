// --png DIR: one picture per frame (bird's-eye view over the range image).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "frontends/frame_sink.hpp"

namespace vlpground::cli {

struct PngOptions {
  std::string dir;  // empty: not requested
};

void add_png_options(CLI::App& cmd, PngOptions& o);
std::unique_ptr<FrameSink> make_png_sink(const PngOptions& o, const PipelineConfig& config);

}  // namespace vlpground::cli
