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

#include "cli/report.hpp"
#include "writers/csv_writer.hpp"
#include "writers/pcd_writer.hpp"
#include "writers/png_writer.hpp"

namespace vlpground::cli {
namespace {

// Blocks SIGINT/SIGTERM/SIGUSR1 in every thread (call before creating any) and turns them,
// or the deadline, into Pipeline::stop() from a dedicated thread. SIGUSR1 ends the watcher.
class StopOnSignal {
 public:
  StopOnSignal() {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    sigaddset(&set_, SIGUSR1);
    pthread_sigmask(SIG_BLOCK, &set_, nullptr);
  }
  void watch(Pipeline& pipeline, double duration_s) {
    thread_ = std::thread([this, &pipeline, duration_s] {
      using Clock = std::chrono::steady_clock;
      const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                               std::chrono::duration<double>(duration_s));
      bool timed = duration_s > 0;
      while (true) {
        int sig = 0;
        if (timed) {
          const auto left = std::max(deadline - Clock::now(), Clock::duration::zero());
          const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
          const timespec limit{static_cast<time_t>(ns / 1'000'000'000),
                               static_cast<long>(ns % 1'000'000'000)};
          sig = sigtimedwait(&set_, nullptr, &limit);
        } else {
          sig = sigwaitinfo(&set_, nullptr);
        }
        if (sig == SIGUSR1) return;
        if (sig == SIGINT || sig == SIGTERM) {
          interrupted_ = true;
          pipeline.stop();
        } else if (sig == -1 && errno == EAGAIN) {
          timed = false;  // --duration reached
          pipeline.stop();
        }
      }
    });
  }
  void finish() {
    if (!thread_.joinable()) return;
    pthread_kill(thread_.native_handle(), SIGUSR1);
    thread_.join();
  }
  ~StopOnSignal() { finish(); }
  [[nodiscard]] bool interrupted() const { return interrupted_; }

 private:
  sigset_t set_{};
  std::thread thread_;
  std::atomic<bool> interrupted_{false};
};

struct Writers {
  std::unique_ptr<CsvWriter> csv;
  std::unique_ptr<PcdWriter> pcd;
  std::unique_ptr<PngWriter> png;
};

Writers open_writers(const OutputOptions& o, double view_radius_m) {
  Writers w;
  if (!o.csv_path.empty()) w.csv = std::make_unique<CsvWriter>(o.csv_path);
  if (!o.pcd_dir.empty()) w.pcd = std::make_unique<PcdWriter>(o.pcd_dir);
  if (!o.png_dir.empty()) w.png = std::make_unique<PngWriter>(o.png_dir, view_radius_m);
  return w;
}

std::string describe_input(const RunRequest& r) {
  if (r.config.pcap) return "pcap " + r.config.pcap->path;
  return "udp " + r.config.udp.bind_address + ":" + std::to_string(r.config.udp.data_port);
}

}  // namespace

int run_pipeline(RunRequest request) {
  const std::string prefix = "vlpground " + request.command + ": ";
  Writers writers;
  try {
    writers = open_writers(request.outputs, request.config.detector.fit_radius_m);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return 1;
  }
  StopOnSignal signals;  // before the pipeline creates its threads
  std::unique_ptr<Pipeline> pipeline;
  try {
    pipeline = std::make_unique<Pipeline>(request.config);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return 2;
  }
  const bool terminal = isatty(STDOUT_FILENO) != 0 && !request.outputs.json;
  const bool frame_lines = !terminal && !request.outputs.json;
  std::atomic<std::uint64_t> warnings{0};
  std::mutex gps_mutex;
  std::string gps;

  pipeline->on_frame([&](const LabelledFrame& f) {
    if (writers.csv) writers.csv->write(f.frame, f.ground);
    if (writers.pcd) writers.pcd->write(f.frame, f.ground);
    if (writers.png) writers.png->write(f.frame, f.ground, f.timings.detect_ms);
    if (frame_lines) print_frame_line(stdout, f);
  });
  pipeline->on_telemetry([&](const PositionPacket& p) {
    static constexpr const char* kPps[] = {"absent", "synchronizing", "locked", "error"};
    char line[96];
    std::snprintf(line, sizeof line, "PPS %s, GPRMC %s", kPps[static_cast<int>(p.pps) & 3],
                  p.gprmc.parsed ? (p.gprmc.valid ? "valid" : "void") : "absent");
    std::lock_guard lock(gps_mutex);
    gps = line;
  });
  pipeline->on_diagnostics([&](const Diagnostic& d) {
    switch (d.kind) {
      case DiagnosticKind::warning:
        ++warnings;
        spdlog::warn("{}", d.message);
        break;
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
    return 1;
  }
  if (!request.config.pcap) {
    std::fprintf(stderr, "%slistening on %s\n", prefix.c_str(), describe_input(request).c_str());
  }
  signals.watch(*pipeline, request.duration_s);
  if (terminal) {
    while (!pipeline->wait_for(100)) print_progress(stdout, pipeline->stats());
    print_progress(stdout, pipeline->stats());
    std::fputc('\n', stdout);
  }
  pipeline->wait();
  signals.finish();
  try {
    if (writers.png) writers.png->finish();  // the run's overview.png
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
  }

  const PipelineStats stats = pipeline->stats();
  SummaryContext context{request.command, describe_input(request), request.config.detector.method,
                         gps, warnings.load()};
  if (request.outputs.json) {
    std::printf("%s\n", summary_json(stats, context).c_str());
  } else {
    print_summary_table(stdout, stats, context);
  }
  std::fflush(stdout);
  if (stats.frames_delivered == 0 && stats.capture.source.data_packets > 0 &&
      !signals.interrupted()) {
    std::fprintf(stderr, "%sno frame decoded from %llu data packets\n", prefix.c_str(),
                 static_cast<unsigned long long>(stats.capture.source.data_packets));
    return 1;
  }
  return 0;
}

}  // namespace vlpground::cli
