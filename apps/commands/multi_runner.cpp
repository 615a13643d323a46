#include "commands/multi_runner.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "commands/run_support.hpp"
#include "vlpground/multi_pipeline.hpp"

namespace vlpground::cli {
namespace {

MultiPipelineConfig multi_config(const RunRequest& request, const std::vector<std::string>& specs) {
  const auto& udp = std::get<UdpSourceConfig>(request.config.source);
  if (!udp.sensor_address.empty()) {
    throw UsageError("--sensor-ip and --sensor exclude each other (--sensor NAME=IP names the "
                     "address of each sensor)");
  }
  if (request.outputs.csv.path == "-") {
    throw UsageError("--csv - with --sensor: give --csv a file (FILE.NAME.csv per sensor)");
  }
  SensorConfig defaults;
  defaults.data_port = udp.data_port;
  defaults.position_port = udp.position_port;
  defaults.extrinsics = request.config.detector.extrinsics;
  MultiPipelineConfig config;
  for (const std::string& spec : specs) {
    try {
      config.sensors.push_back(parse_sensor_spec(spec, defaults));
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--sensor: ") + e.what());
    }
  }
  config.bind_address = udp.bind_address;
  config.multicast_group = udp.multicast_group;
  config.reuse_address = udp.reuse_address;
  config.pipeline = request.config;
  config.pipeline.max_frames =
      RotationLimit::pipeline_max_frames(request.config.max_frames, request.partial);
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--sensor: ") + e.what());
  }
  return config;
}

std::string describe_sensor(const SensorConfig& s) {
  return s.name + " = " + s.address + ":" + std::to_string(s.data_port);
}

}  // namespace

int run_multi_pipeline(RunRequest request, const std::vector<std::string>& specs) {
  const std::string prefix = "vlpground " + request.command + ": ";
  apply_log_level(request.log_level);
  const MultiPipelineConfig config = multi_config(request, specs);  // UsageError: exit 2
  std::unique_ptr<MultiPipeline> multi;
  try {
    multi = std::make_unique<MultiPipeline>(config);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return kExitUsage;
  }
  std::vector<std::unique_ptr<SinkSet>> sinks;  // one set per sensor
  try {
    for (std::size_t i = 0; i < config.sensors.size(); ++i) {
      const std::string& name = config.sensors[i].name;
      PipelineConfig sensor_config = config.pipeline;
      sensor_config.sensor_name = name;
      sensor_config.sensor_index = static_cast<std::uint32_t>(i);
      sensor_config.detector.extrinsics = config.sensors[i].extrinsics;
      sinks.push_back(std::make_unique<SinkSet>(
          make_sinks(outputs_for_sensor(request.outputs, name), sensor_config)));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return kExitFailure;
  }
  StopOnSignal signals;  // before the pipelines create their threads
  const bool terminal = isatty(STDOUT_FILENO) != 0 && !request.json;
  const bool frame_lines = !request.json;
  SinkErrors sink_errors;
  // Per sensor: --frames counts each sensor's rotations; what it says about its capture.
  std::vector<RotationLimit> limits(config.sensors.size(),
                                    RotationLimit(request.config.max_frames, request.partial));
  std::vector<CaptureSummary> captures(config.sensors.size());
  std::mutex capture_mutex;
  // Each sensor's frames arrive on its own detection thread, so each touches only its sinks.
  multi->on_frame([&](const LabelledFrame& f) {
    const std::size_t i = f.sensor_index;
    if (!limits[i].admit(f.frame.meta, [&] { multi->sensor(i).stop(); })) return;
    sinks[i]->write(f, sink_errors, [&] { multi->stop(); });
    if (frame_lines) print_frame_line(stdout, f);
    std::lock_guard lock(capture_mutex);
    captures[i].add_frame(f.frame.meta);
  });
  multi->on_telemetry([&](std::size_t sensor, const PositionPacket& p) {
    sinks[sensor]->on_position(p);
    std::lock_guard lock(capture_mutex);
    captures[sensor].add_position(p);
  });
  multi->on_diagnostics([&](std::size_t sensor, const Diagnostic& d) {
    const std::string& name = config.sensors[sensor].name;
    if (d.kind == DiagnosticKind::warning) {
      spdlog::warn("{}: {}", name, d.message);
      std::lock_guard lock(capture_mutex);
      captures[sensor].add_warning(d.message);
    } else if (d.kind == DiagnosticKind::callback_exception ||
               d.kind == DiagnosticKind::source_error) {
      std::fprintf(stderr, "%s%s: %s\n", prefix.c_str(), name.c_str(), d.message.c_str());
    }
  });
  try {
    multi->start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), e.what());
    return kExitFailure;
  }
  for (const SensorConfig& s : config.sensors) {
    std::fprintf(stderr, "%slistening on %s:%u for %s\n", prefix.c_str(),
                 config.bind_address.c_str(), static_cast<unsigned>(s.data_port),
                 describe_sensor(s).c_str());
  }
  signals.watch([&] { multi->stop(); }, request.duration_s);
  using Clock = std::chrono::steady_clock;
  auto next_stats = Clock::now() + std::chrono::seconds(1);
  while (!multi->wait_for(100)) {
    if (Clock::now() < next_stats) continue;
    next_stats += std::chrono::seconds(1);
    const MultiPipelineStats now = multi->stats();
    for (std::size_t i = 0; i < sinks.size(); ++i) sinks[i]->on_stats(now.sensors[i].pipeline);
  }
  multi->wait();
  signals.finish();
  const MultiPipelineStats stats = multi->stats();
  for (std::size_t i = 0; i < sinks.size(); ++i) {
    sinks[i]->finish(stats.sensors[i].pipeline, sink_errors);
  }
  const UdpRouterCounters& router = stats.router;
  if (request.json) {
    nlohmann::json j = {{"command", request.command},
                        {"router",
                         {{"datagrams", router.records},
                          {"unknown_source", router.unknown_source},
                          {"kernel_drops", router.kernel_drops}}},
                        {"sensors", nlohmann::json::array()}};
    for (std::size_t i = 0; i < stats.sensors.size(); ++i) {
      const SensorStats& s = stats.sensors[i];
      const SummaryContext context{request.command, describe_sensor(config.sensors[i]),
                                   std::string(to_string(config.pipeline.detector.method)),
                                   captures[i]};
      nlohmann::json sensor = nlohmann::json::parse(summary_json(s.pipeline, context));
      sensor["name"] = s.name;
      sensor["packets"]["routed"] = router.sensors[i].data_packets;
      sensor["packets"]["wrong_size"] = router.sensors[i].skipped_wrong_size;
      sensor["packets"]["queue_full"] = s.queue_full;
      j["sensors"].push_back(std::move(sensor));
    }
    std::printf("%s\n", j.dump().c_str());
  } else {
    if (terminal) std::fputc('\n', stdout);
    for (std::size_t i = 0; i < stats.sensors.size(); ++i) {
      const SummaryContext context{request.command + ", sensor " + stats.sensors[i].name,
                                   describe_sensor(config.sensors[i]),
                                   std::string(to_string(config.pipeline.detector.method)),
                                   captures[i]};
      print_summary_table(stdout, stats.sensors[i].pipeline, context);
    }
    std::printf("router: %llu datagrams, %llu from unknown addresses, %llu dropped by the kernel\n",
                static_cast<unsigned long long>(router.records),
                static_cast<unsigned long long>(router.unknown_source),
                static_cast<unsigned long long>(router.kernel_drops));
  }
  std::fflush(stdout);
  if (const std::string error = sink_errors.first(); !error.empty()) {
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), error.c_str());
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace vlpground::cli
