// Shared body of `replay` and `live`: builds the pipeline, the frame sinks and the console
// output, turns SIGINT/SIGTERM (and --duration) into Pipeline::stop(), prints the summary.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "frontends/output_options.hpp"
#include "vlpground/pipeline.hpp"

namespace vlpground::cli {

struct RunRequest {
  std::string command;  // "replay" | "live"
  PipelineConfig config;
  OutputOptions outputs;
  bool json = false;               // summary as JSON on stdout
  std::string log_level = "warn";  // spdlog level name
  double duration_s = 0.0;         // 0 = no time limit
  bool partial = false;            // --frames counts partial rotations too
  bool allow_empty = false;        // live: receiving nothing is not an error
};

/// The options replay and live share: detector, limits, outputs, --json, --log-level, --config.
void add_run_options(CLI::App& cmd, RunRequest& request);

/// Returns the process exit code; prints one-line errors itself.
int run_pipeline(RunRequest request);

}  // namespace vlpground::cli
