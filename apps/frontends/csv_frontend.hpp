// --csv FILE: one row per return (frame,laser_id,ring,return,...,ground), "-" = stdout.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "frontends/frame_sink.hpp"

namespace vlpground::cli {

struct CsvOptions {
  std::string path;  // empty: not requested
};

void add_csv_options(CLI::App& cmd, CsvOptions& o);
std::unique_ptr<FrameSink> make_csv_sink(const CsvOptions& o, const PipelineConfig& config);

}  // namespace vlpground::cli
