// `vlpground replay FILE.pcap [options]`: decode a capture and detect ground.
#include <cstdio>

#include "cli/capture_probe.hpp"
#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "commands/pipeline_runner.hpp"

namespace vlpground::cli {
namespace {

class ReplayCommand : public Command {
 public:
  explicit ReplayCommand(CLI::App& app) {
    request_.command = "replay";
    PcapSourceConfig& pcap = pcap_;
    CLI::App* cmd = app.add_subcommand(
        "replay", "decode a capture (pcap or pcapng) and label ground in every rotation");
    cmd->add_option("capture", pcap.path, "the capture")->type_name("FILE.pcap")->required();
    cmd->add_option("--rate", pcap.rate, "replay speed: 0 = as fast as possible, 1 = real time")
        ->check(CLI::Range(0.0, 1000.0));
    cmd->add_flag("--loop", pcap.loop,
                  "replay the file again and again (until Ctrl-C or --frames)");
    cmd->add_option("--port", pcap.data_port, "UDP data port in the capture")
        ->check(CLI::Range(1, 65535));
    cmd->add_option("--position-port", pcap.position_port, "UDP position port in the capture")
        ->check(CLI::Range(1, 65535));
    cmd->add_option("--sensor-ip", pcap.sensor_address,
                    "only packets from this sensor address (empty: any)")
        ->type_name("IP");
    add_run_options(*cmd, request_);
  }

  int run() override {
    request_.config.pcap = pcap_;
    const CaptureProbe probe = probe_capture(pcap_, 400);
    if (!probe.error.empty()) {
      std::fprintf(stderr, "vlpground replay: %s\n", probe.error.c_str());
      return kExitFailure;
    }
    if (!probe.is_vlp16()) {
      std::fprintf(stderr, "vlpground replay: %s: no VLP-16 packets (%s)\n", pcap_.path.c_str(),
                   probe.verdict().c_str());
      return kExitFailure;
    }
    return run_pipeline(std::move(request_));
  }

 private:
  PcapSourceConfig pcap_;
  RunRequest request_;
};

}  // namespace

<<<<<<< HEAD
int run_replay(int argc, char** argv) {
  const auto specs = replay_specs();
  try {
    const Args args(argc, argv, specs);
    if (args.has("--help")) {
      std::printf(
          "usage: vlpground replay FILE.pcap [options]\n"
          "Decodes a VLP-16 capture (pcap or pcapng) and labels ground in every "
          "rotation.\noptions:\n%s",
          describe_options(specs).c_str());
      return 0;
    }
    if (args.positionals().size() != 1) throw UsageError("expects exactly one FILE.pcap");
    RunRequest request;
    request.command = "replay";
    PcapSourceConfig pcap;
    pcap.path = args.positionals()[0];
    pcap.rate = args.number("--rate", 0.0, 0.0, 1000.0);
    pcap.loop = args.has("--loop");
    pcap.data_port = static_cast<std::uint16_t>(args.integer("--port", 2368, 1, 65535));
    pcap.position_port =
        static_cast<std::uint16_t>(args.integer("--position-port", 8308, 1, 65535));
    pcap.sensor_address = args.text("--sensor-ip", "");
    request.config.source = pcap;
    apply_common_options(args, request.config);
    request.outputs = output_options(args);
    apply_log_level(request.outputs.log_level);
    const CaptureProbe probe = probe_capture(pcap, 400);
    if (!probe.error.empty()) {
      std::fprintf(stderr, "vlpground replay: %s\n", probe.error.c_str());
      return 1;
    }
    if (!probe.is_vlp16()) {
      std::fprintf(stderr, "vlpground replay: %s: no VLP-16 packets (%s)\n", pcap.path.c_str(),
                   probe.verdict().c_str());
      return 1;
    }
    return run_pipeline(std::move(request));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "vlpground replay: %s (see --help)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground replay: %s\n", e.what());
    return 1;
  }
=======
std::unique_ptr<Command> add_replay_command(CLI::App& app) {
  return std::make_unique<ReplayCommand>(app);
>>>>>>> main
}

}  // namespace vlpground::cli
