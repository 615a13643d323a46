// `vlpground eval FILE.pcap --labels FILE.labels [options]`: precision, recall, F1.
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/capture_probe.hpp"
#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "vlpground/evaluation/evaluation.hpp"

namespace vlpground::cli {

int run_eval(int argc, char** argv) {
  std::vector<OptionSpec> specs = {
      {"--labels", true, "FILE  ground truth (one byte per return slot, see data README)"},
      {"--radius", true, "M  score returns within this horizontal range (default 40)"},
      {"--json", false, "print JSON instead of a table"},
  };
  specs.insert(specs.end(), detector_option_specs().begin(), detector_option_specs().end());
  try {
    const Args args(argc, argv, specs);
    if (args.has("--help")) {
      std::printf(
          "usage: vlpground eval FILE.pcap --labels FILE.labels [options]\n"
          "Scores ground labels (ground = positive class) against ground truth.\n"
          "Without --extrinsics, the mounting pose is read from STEM.json beside the\n"
          "capture when present (simulator captures).\noptions:\n%s",
          describe_options(specs).c_str());
      return 0;
    }
    if (args.positionals().size() != 1) throw UsageError("expects exactly one FILE.pcap");
    if (!args.has("--labels")) throw UsageError("--labels FILE is required");
    const std::filesystem::path pcap_path = args.positionals()[0];
    PipelineConfig config;
    apply_common_options(args, config);
    apply_log_level(args.text("--log-level", "warn"));
    const double radius = args.number("--radius", 40.0, 0.1, 1000.0);
    PcapSourceConfig pcap;
    pcap.path = pcap_path.string();
    const CaptureProbe probe = probe_capture(pcap, 400);
    if (!probe.error.empty()) {
      std::fprintf(stderr, "vlpground eval: %s\n", probe.error.c_str());
      return 1;
    }
    if (!probe.is_vlp16()) {
      std::fprintf(stderr, "vlpground eval: %s: no VLP-16 packets (%s)\n", pcap.path.c_str(),
                   probe.verdict().c_str());
      return 1;
    }
    const auto sim_json = std::filesystem::path(pcap_path).replace_extension(".json");
    if (!args.has("--extrinsics") && std::filesystem::exists(sim_json)) {
      config.detector.extrinsics = eval::load_sim_extrinsics(sim_json);
    }
    eval::CaptureScoreOptions options;
    options.score.radius_m = radius;
    options.max_frames = static_cast<int>(config.max_frames);
    const eval::CaptureScore result =
        eval::score_capture(pcap_path, args.text("--labels", ""), config.detector, options);
    const eval::Confusion& c = result.score.all;
    if (args.has("--json")) {
      nlohmann::json j = {
          {"capture", result.capture},
          {"method", to_string(result.method)},
          {"radius_m", radius},
          {"frames", result.score.frames},
          {"precision", c.precision()},
          {"recall", c.recall()},
          {"f1", c.f1()},
          {"tp", c.tp},
          {"fp", c.fp},
          {"fn", c.fn},
          {"tn", c.tn},
          {"detect_ms_total", result.detect_ms_total},
          {"high_obstacle_as_ground_rate", result.score.high_obstacle_as_ground_rate()},
      };
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("%-10s %s\n%-10s %s\n%-10s %llu\n%-10s %.1f m\n", "capture",
                  result.capture.c_str(), "method", to_string(result.method).data(), "frames",
                  static_cast<unsigned long long>(result.score.frames), "radius", radius);
      std::printf("%-10s %.4f\n%-10s %.4f\n%-10s %.4f\n", "precision", c.precision(), "recall",
                  c.recall(), "F1", c.f1());
      std::printf("%-10s tp %llu, fp %llu, fn %llu, tn %llu\n", "counts",
                  static_cast<unsigned long long>(c.tp), static_cast<unsigned long long>(c.fp),
                  static_cast<unsigned long long>(c.fn), static_cast<unsigned long long>(c.tn));
    }
    return 0;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "vlpground eval: %s (see --help)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground eval: %s\n", e.what());
    return 1;
  }
}

}  // namespace vlpground::cli
