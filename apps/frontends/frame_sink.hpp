// Where labelled frames go besides the console: CSV, PCD, PNG files, and the front-ends of
// other helpers (ROS 2, Foxglove, MCAP). The runner (commands/pipeline_runner.cpp) holds one
// FrameSink per requested front-end and calls them.
//
// To add a front-end NAME:
//   1. apps/frontends/NAME_frontend.{hpp,cpp}: `struct NameOptions` (defaults in-class),
//      `void add_NAME_options(CLI::App& cmd, NameOptions& o)` (an option group) and
//      `std::unique_ptr<FrameSink> make_NAME_sink(const NameOptions&, const PipelineConfig&)`
//      returning nullptr when the user did not ask for it.
//   2. apps/frontends/output_options.hpp: one member `NameOptions NAME;` in OutputOptions.
//   3. apps/frontends/output_options.cpp: one line in add_output_options() and one in
//      make_sinks(); add the .cpp to apps/CMakeLists.txt. Then regenerate the option reference:
//      `cmake --build build --target cli_docs` (docs/cli.md; a test compares it).
//
// Errors: a sink that cannot write throws std::runtime_error with a one-line reason naming
// the option and the file ("--csv out.csv: No space left on device"); the runner then stops
// the run, flushes the other sinks and exits with status 1.
#pragma once

#include "vlpground/pipeline.hpp"

namespace vlpground::cli {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  /// Called on the detection thread for every delivered frame; `f` is valid during the call.
  virtual void write(const LabelledFrame& f) = 0;
  /// About once a second, from the runner's main thread, and once more with the final
  /// counters just before finish().
  virtual void on_stats(const PipelineStats& /*stats*/) {}
  /// Every position packet (PPS, $GPRMC), on the acquisition thread.
  virtual void on_position(const PositionPacket& /*packet*/) {}
  /// End of the run: flush and close. Throws std::runtime_error with a one-line reason when
  /// the output could not be written.
  virtual void finish() {}
};

}  // namespace vlpground::cli
