// --pcd DIR: one binary PCD per frame (x y z intensity ring time label).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "frontends/frame_sink.hpp"

namespace vlpground::cli {

struct PcdOptions {
  std::string dir;  // empty: not requested
};

void add_pcd_options(CLI::App& cmd, PcdOptions& o);
std::unique_ptr<FrameSink> make_pcd_sink(const PcdOptions& o, const PipelineConfig& config);

}  // namespace vlpground::cli
