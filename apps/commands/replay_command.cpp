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
                  "replay the file again and again (until Ctrl-C or --frames), joined as one "
                  "continuous recording: each pass starts where the previous one's rotation "
                  "ends (the packets before are skipped, counted), so every frame stays a full "
                  "rotation");
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
    request_.config.source = pcap_;
    check_input_file("capture", pcap_.path);
    if (!request_.config.decoder.calibration_file.empty()) {
      check_input_file("--calibration", request_.config.decoder.calibration_file);
    }
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

std::unique_ptr<Command> add_replay_command(CLI::App& app) {
  return std::make_unique<ReplayCommand>(app);
}

}  // namespace vlpground::cli
