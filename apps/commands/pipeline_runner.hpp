// Shared body of `replay` and `live`: builds the pipeline, wires the writers and the console
// output, turns SIGINT/SIGTERM (and --duration) into Pipeline::stop(), prints the summary.
#pragma once

#include <string>

#include "cli/options.hpp"
#include "vlpground/pipeline.hpp"

namespace vlpground::cli {

struct RunRequest {
  std::string command;  // "replay" | "live"
  PipelineConfig config;
  OutputOptions outputs;
  double duration_s = 0.0;  // 0 = no time limit
};

/// Returns the process exit code; prints one-line errors itself.
int run_pipeline(RunRequest request);

}  // namespace vlpground::cli
