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

std::unique_ptr<Command> add_live_command(CLI::App& app) {
  return std::make_unique<LiveCommand>(app);
}

}  // namespace vlpground::cli
