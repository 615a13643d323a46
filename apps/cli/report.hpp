// Console output of replay/live: per-frame lines (no terminal) or a progress bar (terminal),
// and the final summary as a table or JSON.
#pragma once

#include <cstdio>
#include <string>

#include "cli/capture_summary.hpp"
#include "vlpground/pipeline.hpp"

namespace vlpground::cli {

/// "frame 3: 1808 columns, 28931 returns, 41.2% ground, 1.9 ms detect" into `to`, flushed
/// (preceded by the sensor name when the frame has one).
void print_frame_line(std::FILE* to, const LabelledFrame& f);

/// Redraws one progress line (frames, percent of the file, frames/s) on a terminal.
void print_progress(std::FILE* to, const PipelineStats& s);

struct SummaryContext {
  std::string command;  // "replay" | "live"
  std::string input;    // source description
  std::string method;
  CaptureSummary capture;  // model, rpm, GPS/PPS, warnings... (the fields `info --json` shares)
  // Seconds from the first packet to the last delivered frame (live); < 0: use elapsed_s.
  double active_s = -1.0;
};

/// Percentiles need samples: p50 from kMinSamplesP50, p99 (and a verdict on the latency goal)
/// from kMinSamplesP99; below that, only the count, mean and maximum are reported.
inline constexpr std::uint64_t kMinSamplesP50 = 10;
inline constexpr std::uint64_t kMinSamplesP99 = 100;

void print_summary_table(std::FILE* to, const PipelineStats& s, const SummaryContext& c);
std::string summary_json(const PipelineStats& s, const SummaryContext& c);

}  // namespace vlpground::cli
