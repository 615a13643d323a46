#include "commands/pipeline_runner.hpp"

#include <pthread.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <ctime>
#include <memory>
#include <mutex>
#include <thread>

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "cli/yaml_config.hpp"
#include "commands/run_support.hpp"

namespace vlpground::cli {
namespace {

// Host time from the first packet to the last delivered frame, from the frames' stamps: the
// first frame began (last_time_ns - first_time_ns) before the packet that completed it.
class ActiveSpan {
 public:
  void add(const FrameMeta& m) {
    if (m.completed_receive_ns <= 0) return;
    std::lock_guard lock(mutex_);
    if (first_ns_ == 0) first_ns_ = m.completed_receive_ns - (m.last_time_ns - m.first_time_ns);
    last_ns_ = m.completed_receive_ns;
  }
  [[nodiscard]] double seconds() const {
    std::lock_guard lock(mutex_);
    return first_ns_ == 0 ? 0.0 : static_cast<double>(last_ns_ - first_ns_) * 1e-9;
  }

 private:
  mutable std::mutex mutex_;
  std::int64_t first_ns_ = 0, last_ns_ = 0;
};

// One line saying why a run found no ground at all, with the settings that decide it.
std::string no_ground_reason(const DetectorConfig& d) {
  char text[400];
  std::snprintf(text, sizeof text,
                "no ground in any frame: no plane found %.2f..%.2f m under the sensor "
                "(--min-sensor-height) tilted at most %.0f deg; a sensor on a desk or floor "
                "needs --min-sensor-height 0, a tilted mount its roll and pitch in --extrinsics",
                d.min_sensor_height_m, d.max_sensor_height_m, d.max_tilt_deg);
  return text;
}

std::string describe_input(const RunRequest& r) {
  return describe(r.config.source);
}

}  // namespace

int run_pipeline(RunRequest request) {
  const std::string prefix = "vlpground " + request.command + ": ";
  apply_log_level(request.log_level);
  if (request.json && request.outputs.csv.path == "-") {
    throw UsageError("--json and --csv - both write to stdout; give --csv a file");
  }
  std::unique_ptr<SinkSet> sinks;
  try {
    sinks = std::make_unique<SinkSet>(make_sinks(request.outputs, request.config));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return kExitFailure;
  }
  StopOnSignal signals;  // before the pipeline creates its threads
  std::unique_ptr<Pipeline> pipeline;
  try {
    PipelineConfig config = request.config;
    config.max_frames = RotationLimit::pipeline_max_frames(config.max_frames, request.partial);
    pipeline = std::make_unique<Pipeline>(config);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return kExitUsage;
  }
  // stdout carries only the requested output: the CSV with --csv -, else the console.
  std::FILE* const console = request.outputs.csv.path == "-" ? stderr : stdout;
  const bool terminal = isatty(fileno(console)) != 0 && !request.json;
  const bool frame_lines = !terminal && !request.json && console == stdout;
  SinkErrors sink_errors;
  ActiveSpan span;
  std::mutex capture_mutex;  // frames (detection thread), telemetry and warnings (acquisition)
  CaptureSummary capture;

  RotationLimit limit(request.config.max_frames, request.partial);  // detection thread only
  // --loop --frames N of a capture that never yields a full rotation (shorter than one, or
  // with gaps in every one) would run forever: the run ends with an error instead.
  const auto* pcap = std::get_if<PcapSourceConfig>(&request.config.source);
  LoopWithoutRotation endless(pcap != nullptr && pcap->loop && limit.counts_rotations(),
                              request.config.queue_frames);
  pipeline->on_frame([&](const LabelledFrame& f) {
    if (endless.check(f.frame.meta, [&] { return pipeline->stats().capture.source.loop_wraps; })) {
      pipeline->stop();
      return;
    }
    if (!limit.admit(f.frame.meta, [&] { pipeline->stop(); })) return;  // stopping
    sinks->write(f, sink_errors, [&] { pipeline->stop(); });
    if (frame_lines) print_frame_line(stdout, f);
    span.add(f.frame.meta);
    std::lock_guard lock(capture_mutex);
    capture.add_frame(f.frame.meta);
  });
  pipeline->on_telemetry([&](const PositionPacket& p) {
    sinks->on_position(p);
    std::lock_guard lock(capture_mutex);
    capture.add_position(p);
  });
  pipeline->on_diagnostics([&](const Diagnostic& d) {
    switch (d.kind) {
      case DiagnosticKind::warning: {
        spdlog::warn("{}", d.message);
        std::lock_guard lock(capture_mutex);
        capture.add_warning(d.message);
        break;
      }
      case DiagnosticKind::callback_exception:
      case DiagnosticKind::source_error:
        std::fprintf(stderr, "%s%s\n", prefix.c_str(), d.message.c_str());
        break;
      case DiagnosticKind::frame_dropped:
        spdlog::debug("{}", d.message);
        break;
      case DiagnosticKind::finished:
        spdlog::info("pipeline {}", d.message);
        break;
    }
  });

  try {
    pipeline->start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return kExitFailure;
  }
  if (!std::holds_alternative<PcapSourceConfig>(request.config.source)) {
    std::fprintf(stderr, "%slistening on %s\n", prefix.c_str(), describe_input(request).c_str());
  }
  signals.watch([&] { pipeline->stop(); }, request.duration_s);
  using Clock = std::chrono::steady_clock;
  auto next_stats = Clock::now() + std::chrono::seconds(1);
  while (!pipeline->wait_for(100)) {
    if (terminal) print_progress(console, pipeline->stats());
    if (Clock::now() >= next_stats) {
      next_stats += std::chrono::seconds(1);
      sinks->on_stats(pipeline->stats());
    }
  }
  if (terminal) {
    print_progress(console, pipeline->stats());
    std::fputc('\n', console);
  }
  pipeline->wait();
  signals.finish();
  sinks->finish(pipeline->stats(), sink_errors);

  const PipelineStats stats = pipeline->stats();
  SummaryContext context{request.command, describe_input(request),
                         std::string(to_string(request.config.detector.method)), capture};
  if (stats.live) context.active_s = span.seconds();
  if (request.json) {
    std::printf("%s\n", summary_json(stats, context).c_str());
  } else {
    print_summary_table(console, stats, context);
  }
  std::fflush(stdout);
  if (endless.ended()) {
    std::fprintf(stderr,
                 "%s--frames %llu counts full rotations, and %llu passes of the looped capture "
                 "gave none (shorter than a rotation, or gaps in every one); add --partial to "
                 "count every frame\n",
                 prefix.c_str(), static_cast<unsigned long long>(request.config.max_frames),
                 static_cast<unsigned long long>(stats.capture.source.loop_wraps));
    return kExitFailure;
  }
  if (const std::string error = sink_errors.first(); !error.empty()) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), error.c_str());
    return kExitFailure;
  }
  if (stats.live && stats.capture.source.data_packets == 0) {
    std::fprintf(stderr, "%sno packets received on %s%s\n", prefix.c_str(),
                 describe_input(request).c_str(),
                 request.allow_empty ? " (--allow-empty)"
                                     : "; check the port and --bind, or pass --allow-empty");
    return request.allow_empty ? kExitOk : kExitFailure;
  }
  if (stats.frames_delivered > 0 && stats.ground_returns == 0) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(),
                 no_ground_reason(request.config.detector).c_str());
  }
  if (stats.frames_delivered == 0 && stats.capture.source.data_packets > 0 &&
      !signals.interrupted()) {
    std::fprintf(stderr, "%sno frame decoded from %llu data packets\n", prefix.c_str(),
                 static_cast<unsigned long long>(stats.capture.source.data_packets));
    return kExitFailure;
  }
  return kExitOk;
}

void add_run_options(CLI::App& cmd, RunRequest& request) {
  add_run_limit_options(cmd, request.config);
  cmd.add_flag("--partial", request.partial,
               "--frames N counts partial rotations too (by default only full ones: the "
               "partial first and last frames are output but not counted)");
  add_output_options(cmd, request.outputs);
  cmd.add_flag("--json", request.json,
               "print a machine-readable JSON summary instead of the table (stdout carries "
               "only that document)")
      ->group("Outputs");
  add_detector_options(cmd, request.config);
  add_log_level_option(cmd, request.log_level);
  add_config_file_option(cmd);
}

}  // namespace vlpground::cli
