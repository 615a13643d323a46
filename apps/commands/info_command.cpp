// `vlpground info FILE.pcap [--json]`: what is in a capture.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/capture_probe.hpp"
#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "vlpground/driver/capture_reader.hpp"

namespace vlpground::cli {
namespace {

struct CaptureFacts {
  std::uint64_t frames = 0, complete_frames = 0;
  double rpm_sum = 0, partial_rpm_sum = 0;
  std::uint64_t partial_rpm_frames = 0;
  std::int64_t first_ns = 0, last_ns = 0;
  std::string mode;
  std::string decoded_model;
  CaptureCounters counters;
  std::uint64_t position_parsed = 0;
  PpsStatus pps = PpsStatus::absent;
  bool gprmc_seen = false, gprmc_valid = false;
  std::string gprmc_time;
  std::vector<std::string> warnings;
};

CaptureFacts read_frames(const PcapSourceConfig& pcap, const DecoderConfig& decoder) {
  CaptureFacts facts;
  CaptureReader reader(open_pcap_source(pcap), decoder);
  reader.on_position([&](const PositionPacket& p) {
    ++facts.position_parsed;
    facts.pps = p.pps;
    if (p.gprmc.parsed) {
      facts.gprmc_seen = true;
      facts.gprmc_valid = p.gprmc.valid;
      char t[64];
      std::snprintf(t, sizeof t, "%04d-%02d-%02d %02d:%02d:%06.3f UTC", p.gprmc.year, p.gprmc.month,
                    p.gprmc.day, p.gprmc.hour, p.gprmc.minute, p.gprmc.second);
      facts.gprmc_time = t;
    }
  });
  reader.on_warning([&](std::error_code, const std::string& w) { facts.warnings.push_back(w); });
  Frame frame;
  while (reader.next(frame) == ReadStatus::frame) {
    if (facts.frames == 0) facts.first_ns = frame.meta.first_time_ns;
    facts.last_ns = frame.meta.last_time_ns;
    ++facts.frames;
    if (frame.meta.complete) {
      ++facts.complete_frames;
      facts.rpm_sum += frame.meta.rpm;
    } else if (frame.meta.rpm > 0) {
      facts.partial_rpm_sum += frame.meta.rpm;  // short captures: no complete rotation
      ++facts.partial_rpm_frames;
    }
    facts.mode = std::string(to_string(frame.meta.mode));
    facts.decoded_model = std::string(to_string(frame.meta.model));
  }
  facts.counters = reader.counters();
  return facts;
}

const char* mode_name(std::uint8_t byte) {
  switch (byte) {
    case kModeStrongest:
      return "strongest";
    case kModeLast:
      return "last";
    case kModeDual:
      return "dual";
    default:
      return "unknown";
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
    if (vlp16) facts = read_frames(pcap, decoder_);
    const auto& src = vlp16 ? facts.counters.source : probe.counters;
    // Complete rotations measure the rpm best; a short capture falls back on partial ones.
    const double rpm =
        facts.complete_frames ? facts.rpm_sum / static_cast<double>(facts.complete_frames)
        : facts.partial_rpm_frames
            ? facts.partial_rpm_sum / static_cast<double>(facts.partial_rpm_frames)
            : 0.0;
    const double duration_s = static_cast<double>(facts.last_ns - facts.first_ns) * 1e-9;
    std::optional<bool> product_agrees;
    const std::string product = describe_product(probe, product_agrees);
    const std::string model =
        vlp16 ? probe.family() : probe.family() + " - not a VLP-16 (" + probe.verdict() + ")";

    if (json_) {
      nlohmann::json j = {
          {"file", pcap.path},
          {"model", probe.family()},
          {"is_vlp16", vlp16},
          {"product_byte", probe.data_packets ? nlohmann::json(probe.main_product()) : nlohmann::json()},
          {"product_byte_agrees_with_timing",
           product_agrees ? nlohmann::json(*product_agrees) : nlohmann::json()},
          {"packet_spacing_us", probe.median_spacing_us},
          {"return_mode", mode_name(probe.main_mode())},
          {"rpm", rpm},
          {"rotations", facts.complete_frames},
          {"frames", facts.frames},
          {"duration_s", duration_s},
          {"packets",
           {{"data", src.data_packets},
            {"position", src.position_packets},
            {"skipped", src.skipped()},
            {"truncated", src.truncated},
            {"lost", facts.counters.assembler.packets_lost}}},
          {"gps",
           {{"pps", pps_name(facts.pps)},
            {"gprmc", facts.gprmc_seen ? (facts.gprmc_valid ? "valid" : "void") : "absent"},
            {"time", facts.gprmc_time}}},
          {"warnings", facts.warnings},
      };
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
      std::printf("%-14s %s\n", "file", pcap.path.c_str());
      std::printf("%-14s %s\n", "model", model.c_str());
      std::printf("%-14s %s\n", "product byte", product.c_str());
      std::printf("%-14s %.1f us\n", "packet spacing", probe.median_spacing_us);
      std::printf("%-14s %s\n", "return mode", mode_name(probe.main_mode()));
      if (vlp16) {
        std::printf("%-14s %.1f\n", "rpm", rpm);
        std::printf("%-14s %llu complete (%llu frame%s with partial ones)\n", "rotations",
                    u(facts.complete_frames), u(facts.frames), plural(facts.frames));
        std::printf("%-14s %.3f s\n", "duration", duration_s);
      }
      std::printf("%-14s %llu data, %llu position, %llu skipped, %llu truncated, %llu lost\n",
                  "packets", u(src.data_packets), u(src.position_packets), u(src.skipped()),
                  u(src.truncated), u(facts.counters.assembler.packets_lost));
      std::printf("%-14s PPS %s, GPRMC %s%s%s\n", "gps", pps_name(facts.pps),
                  facts.gprmc_seen ? (facts.gprmc_valid ? "valid" : "void") : "absent",
                  facts.gprmc_time.empty() ? "" : ", ", facts.gprmc_time.c_str());
      for (const auto& w : facts.warnings) std::printf("%-14s %s\n", "warning", w.c_str());
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
