// `vlpground live [options]`: run on a sensor on the network until Ctrl-C, --frames or
// --duration.
#include <cstdio>

#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "commands/pipeline_runner.hpp"

namespace vlpground::cli {
namespace {

class LiveCommand : public Command {
 public:
  explicit LiveCommand(CLI::App& app) {
    request_.command = "live";
    UdpSourceConfig& udp = request_.config.udp;
    CLI::App* cmd = app.add_subcommand(
        "live",
        "receive packets over UDP and label ground in every rotation; stops on Ctrl-C "
        "(SIGINT/SIGTERM), after --frames N or --duration SECONDS, then prints the summary");
    cmd->add_option("--port", udp.data_port, "UDP data port")->check(CLI::Range(1, 65535));
    cmd->add_option("--position-port", udp.position_port, "UDP position port, 0 = ignore")
        ->check(CLI::Range(0, 65535));
    cmd->add_option("--bind", udp.bind_address, "local address to bind")->type_name("ADDR");
    cmd->add_option("--sensor-ip", udp.sensor_address,
                    "accept packets from this sensor only (empty: any)")
        ->type_name("IP");
    cmd->add_option("--multicast", udp.multicast_group, "join this multicast group (empty: none)")
        ->type_name("GROUP");
    cmd->add_option("--duration", request_.duration_s, "stop after this long (0 = no limit)")
        ->type_name("SECONDS")
        ->check(CLI::Range(0.0, 1e9));
    cmd->add_flag_function(
        "--no-drop", [this](std::int64_t) { request_.config.backpressure = Backpressure::block; },
        "block instead of dropping the oldest frame when the detector lags");
    add_run_options(*cmd, request_);
  }

  int run() override {
    const UdpSourceConfig& udp = request_.config.udp;
    if (udp.position_port == udp.data_port) {
      throw UsageError("--position-port must differ from --port (both " +
                       std::to_string(udp.data_port) + ")");
    }
    return run_pipeline(std::move(request_));
  }

 private:
  RunRequest request_;
};

}  // namespace

<<<<<<< HEAD
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
=======
std::unique_ptr<Command> add_live_command(CLI::App& app) {
  return std::make_unique<LiveCommand>(app);
>>>>>>> main
}

}  // namespace vlpground::cli
