// `vlpground info FILE.pcap [--json]`: what is in a capture.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/capture_probe.hpp"
#include "cli/capture_summary.hpp"
#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "vlpground/driver/capture_reader.hpp"

namespace vlpground::cli {
namespace {

struct CaptureFacts {
  CaptureSummary summary;
  CaptureCounters counters;
};

CaptureFacts read_frames(const PcapSourceConfig& pcap, const DecoderConfig& decoder) {
  CaptureFacts facts;
  CaptureReader reader(open_pcap_source(pcap), decoder);
  reader.on_position([&](const PositionPacket& p) { facts.summary.add_position(p); });
  reader.on_warning(
      [&](std::error_code, const std::string& w) { facts.summary.add_warning(w); });
  Frame frame;
  while (reader.next(frame) == ReadStatus::frame) facts.summary.add_frame(frame.meta);
  facts.counters = reader.counters();
  return facts;
}

std::optional<ReturnMode> mode_of_byte(std::uint8_t byte) {
  switch (byte) {
    case kModeStrongest:
      return ReturnMode::strongest;
    case kModeLast:
      return ReturnMode::last;
    case kModeDual:
      return ReturnMode::dual;
    default:
      return std::nullopt;
  }
}

// "0x22 (VLP-16, agrees with the packet timing)"; no verdict without data packets.
std::string describe_product(const CaptureProbe& probe, std::optional<bool>& agrees) {
  if (probe.data_packets == 0) return "none (no data packets)";
  const std::uint8_t p = probe.main_product();
  const char* named = p == kProductVlp16   ? "VLP-16"
                      : p == kProductHiRes ? "Puck Hi-Res"
                      : p == 0x21          ? "HDL-32E"
                      : p == 0x28          ? "VLP-32C"
                                           : "unknown";
  if (p == kProductVlp16 || p == kProductHiRes) {
    agrees = probe.timing_is_vlp16();
  } else if (p == 0x21) {
    agrees = probe.family() == "HDL-32E";  // the byte and a non-VLP-16 timing agree
  }
  char text[128];
  std::snprintf(text, sizeof text, "0x%02x (%s%s)", p, named,
                !agrees   ? ", not checked against the timing"
                : *agrees ? ", agrees with the packet timing"
                          : ", does NOT agree with the packet timing");
  return text;
}

const char* plural(std::uint64_t n) { return n == 1 ? "" : "s"; }

class InfoCommand : public Command {
 public:
  explicit InfoCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand(
        "info",
        "describe a capture: model, return mode, rpm, rotations, duration, packet counts, GPS/PPS");
    cmd->add_option("capture", pcap_.path, "the capture")->type_name("FILE.pcap")->required();
    cmd->add_flag("--json", json_, "print JSON instead of a table");
    cmd->add_option("--port", pcap_.data_port, "UDP data port in the capture")
        ->check(CLI::Range(1, 65535));
    cmd->add_option("--position-port", pcap_.position_port, "UDP position port in the capture")
        ->check(CLI::Range(1, 65535));
    cmd->add_option_function<std::string>(
           "--model",
           [this](const std::string& m) {
             decoder_.force_model = m == "hires" ? Model::hires : Model::vlp16;
           },
           "decode as this model whatever the product byte says")
        ->check(CLI::IsMember({"vlp16", "hires"}))
        ->default_str("from the product byte");
  }

  int run() override {
    const PcapSourceConfig& pcap = pcap_;
    const CaptureProbe probe = probe_capture(pcap, 0);
    if (!probe.error.empty()) {
      std::fprintf(stderr, "vlpground info: %s\n", probe.error.c_str());
      return kExitFailure;
    }
    const bool vlp16 = probe.is_vlp16();
    CaptureFacts facts;
    if (vlp16) {
      facts = read_frames(pcap, decoder_);
    } else {
      facts.counters.source = probe.counters;
    }
    // No frame decoded (another sensor family): the return-mode byte still tells the mode.
    facts.summary.set_mode_if_unknown(mode_of_byte(probe.main_mode()));
    const CaptureSummary& summary = facts.summary;
    const auto& src = facts.counters.source;
    std::optional<bool> product_agrees;
    const std::string product = describe_product(probe, product_agrees);
    const std::string family =
        vlp16 ? probe.family() : probe.family() + " - not a VLP-16 (" + probe.verdict() + ")";

    if (json_) {
      nlohmann::json j = {
          {"file", pcap.path},
          {"family", probe.family()},
          {"is_vlp16", vlp16},
          {"product_byte", probe.data_packets ? nlohmann::json(probe.main_product()) : nlohmann::json()},
          {"product_byte_agrees_with_timing",
           product_agrees ? nlohmann::json(*product_agrees) : nlohmann::json()},
          {"packet_spacing_us", probe.median_spacing_us},
          {"frames", frames_json(summary.frames(), summary.frames() - summary.complete_frames())},
          {"packets", packets_json(facts.counters)},
      };
      summary.add_json_fields(j);
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
      const auto frames = summary.frames();
      std::printf("%-14s %s\n", "file", pcap.path.c_str());
      std::printf("%-14s %s\n", "model", family.c_str());
      std::printf("%-14s %s\n", "product byte", product.c_str());
      std::printf("%-14s %.1f us\n", "packet spacing", probe.median_spacing_us);
      const auto mode = summary.return_mode();
      std::printf("%-14s %s\n", "return mode", mode ? to_string(*mode).data() : "unknown");
      if (vlp16) {
        std::printf("%-14s %.1f\n", "rpm", summary.rpm().value_or(0.0));
        std::printf("%-14s %llu complete (%llu frame%s with partial ones)\n", "rotations",
                    u(summary.complete_frames()), u(frames), plural(frames));
        std::printf("%-14s %.3f s\n", "duration", summary.duration_s());
      }
      std::printf("%-14s %llu data, %llu position, %llu skipped, %llu truncated, %llu lost\n",
                  "packets", u(src.data_packets), u(src.position_packets), u(src.skipped()),
                  u(src.truncated), u(facts.counters.assembler.packets_lost));
      std::printf("%-14s %s\n", "gps", summary.gps_line().c_str());
      for (const auto& w : summary.warnings()) std::printf("%-14s %s\n", "warning", w.c_str());
    }
    if (!vlp16) {
      std::fprintf(stderr, "vlpground info: %s: not a VLP-16 capture (%s)\n", pcap.path.c_str(),
                   probe.verdict().c_str());
      return kExitFailure;
    }
    return kExitOk;
  }

 private:
  PcapSourceConfig pcap_;
  DecoderConfig decoder_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<Command> add_info_command(CLI::App& app) {
  return std::make_unique<InfoCommand>(app);
}

}  // namespace vlpground::cli
