// `vlpground live [options]`: run on a sensor on the network until Ctrl-C, --frames or
// --duration.
#include <cstdio>

#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "commands/pipeline_runner.hpp"

namespace vlpground::cli {
namespace {

std::vector<OptionSpec> live_specs() {
  std::vector<OptionSpec> specs = {
      {"--port", true, "N  UDP data port (default 2368)"},
      {"--position-port", true, "N  UDP position port, 0 = ignore (default 8308)"},
      {"--bind", true, "ADDR  local address to bind (default 0.0.0.0)"},
      {"--sensor-ip", true, "IP  accept packets from this sensor only"},
      {"--multicast", true, "GROUP  join this multicast group"},
      {"--duration", true, "SECONDS  stop after this long"},
      {"--no-drop", false, "block instead of dropping the oldest frame when the detector lags"},
  };
  for (const auto* group : {&output_option_specs(), &detector_option_specs()}) {
    specs.insert(specs.end(), group->begin(), group->end());
  }
  return specs;
}

}  // namespace

int run_live(int argc, char** argv) {
  const auto specs = live_specs();
  try {
    const Args args(argc, argv, specs);
    if (args.has("--help")) {
      std::printf(
          "usage: vlpground live [options]\n"
          "Receives VLP-16 packets over UDP and labels ground in every rotation.\n"
          "Stops on Ctrl-C (SIGINT/SIGTERM), after --frames N or --duration SECONDS,\n"
          "then prints the summary.\noptions:\n%s",
          describe_options(specs).c_str());
      return 0;
    }
    if (!args.positionals().empty()) {
      throw UsageError("unexpected argument '" + args.positionals()[0] + "'");
    }
    RunRequest request;
    request.command = "live";
    auto& udp = request.config.source.emplace<UdpSourceConfig>();
    udp.data_port = static_cast<std::uint16_t>(args.integer("--port", 2368, 1, 65535));
    udp.position_port = static_cast<std::uint16_t>(args.integer("--position-port", 8308, 0, 65535));
    udp.bind_address = args.text("--bind", "0.0.0.0");
    udp.sensor_address = args.text("--sensor-ip", "");
    udp.multicast_group = args.text("--multicast", "");
    if (udp.position_port == udp.data_port) {
      throw UsageError("--position-port must differ from --port");
    }
    request.duration_s = args.number("--duration", 0.0, 0.0, 1e9);
    if (args.has("--no-drop")) request.config.backpressure = Backpressure::block;
    apply_common_options(args, request.config);
    request.outputs = output_options(args);
    apply_log_level(request.outputs.log_level);
    return run_pipeline(std::move(request));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "vlpground live: %s (see --help)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground live: %s\n", e.what());
    return 1;
  }
}

}  // namespace vlpground::cli
