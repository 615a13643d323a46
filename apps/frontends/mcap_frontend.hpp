// --mcap FILE [--mcap-compression zstd|lz4|none]: records the Foxglove channels of every
// frame (points, ground, range image, status) to an MCAP file (docs/mcap.md).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "frontends/frame_sink.hpp"
#include "vlpground/mcap/writer.hpp"

namespace vlpground::cli {

struct McapOptions {
  std::string path;  // empty: not requested
  mcap::Compression compression = mcap::WriterConfig{}.compression;
};

void add_mcap_options(CLI::App& cmd, McapOptions& o);
std::unique_ptr<FrameSink> make_mcap_sink(const McapOptions& o, const PipelineConfig& config);

}  // namespace vlpground::cli
