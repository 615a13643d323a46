// `vlpground live [options]`: run on a sensor on the network until Ctrl-C, --frames or
// --duration.
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <stdexcept>

#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "commands/multi_runner.hpp"
#include "commands/pipeline_runner.hpp"

namespace vlpground::cli {
namespace {

// Binds (and closes) a UDP socket on `address`:`port` so that a port in use is reported in
// the user's words, naming its role and the option that moves it.
void check_port_free(const std::string& address, std::uint16_t port, const char* role,
                     const char* hint) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICHOST | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (getaddrinfo(address.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) {
    throw std::runtime_error("--bind " + address + ": not a numeric IPv4 or IPv6 address");
  }
  const int fd = socket(found->ai_family, found->ai_socktype, 0);
  const bool in_use =
      fd >= 0 && bind(fd, found->ai_addr, found->ai_addrlen) != 0 && errno == EADDRINUSE;
  if (fd >= 0) close(fd);
  freeaddrinfo(found);
  if (in_use) {
    throw std::runtime_error(std::string(role) + " " + std::to_string(port) + " on " + address +
                             " is in use; " + hint);
  }
}

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
    cmd->add_option("--sensor", sensors_,
                    "one of several sensors, repeatable: NAME=IP[:PORT][@x,y,z,roll,pitch,yaw] "
                    "(port default --port, pose default --extrinsics); packets are routed by "
                    "source address, outputs go per sensor (FILE.NAME.csv, DIR/NAME/)")
        ->type_name("SPEC");
    cmd->add_option("--duration", request_.duration_s, "stop after this long (0 = no limit)")
        ->type_name("SECONDS")
        ->check(CLI::Range(0.0, 1e9));
    cmd->add_flag_function(
        "--no-drop", [this](std::int64_t) { request_.config.backpressure = Backpressure::block; },
        "block instead of dropping the oldest frame when the detector lags");
    cmd->add_flag("--allow-empty", request_.allow_empty,
                  "exit 0 when no packet was received (else exit 1)");
    add_run_options(*cmd, request_);
  }

  int run() override {
    const UdpSourceConfig& udp = request_.config.udp;
    if (udp.position_port == udp.data_port) {
      throw UsageError("--position-port must differ from --port (both " +
                       std::to_string(udp.data_port) + ")");
    }
    if (!request_.config.decoder.calibration_file.empty()) {
      check_input_file("--calibration", request_.config.decoder.calibration_file);
    }
    // Several sensors: the router binds each sensor's port and names a busy one itself.
    if (!sensors_.empty()) return run_multi_pipeline(std::move(request_), sensors_);
    if (udp.multicast_group.empty()) {
      check_port_free(udp.bind_address, udp.data_port, "data port", "choose another with --port");
      if (udp.position_port != 0) {
        check_port_free(udp.bind_address, udp.position_port, "position port",
                        "use --position-port (0 = ignore position packets)");
      }
    }
    return run_pipeline(std::move(request_));
  }

 private:
  RunRequest request_;
  std::vector<std::string> sensors_;
};

}  // namespace

std::unique_ptr<Command> add_live_command(CLI::App& app) {
  return std::make_unique<LiveCommand>(app);
}

}  // namespace vlpground::cli
