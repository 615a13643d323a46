// `vlpground eval FILE.pcap --labels FILE.labels [options]`: precision, recall, F1.
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/capture_probe.hpp"
#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "vlpground/evaluation/evaluation.hpp"

namespace vlpground::cli {

namespace {

class EvalCommand : public Command {
 public:
  explicit EvalCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand(
        "eval",
        "score ground labels (ground = positive class) against ground truth. Without "
        "--extrinsics, the mounting pose is read from STEM.json beside the capture when "
        "present (simulator captures)");
    cmd->add_option("capture", pcap_path_, "the capture")->type_name("FILE.pcap")->required();
    cmd->add_option("--labels", labels_path_,
                    "ground truth: one byte per return slot (README, Data formats); the "
                    "exact heights above the terrain are read from X.heights beside X.labels "
                    "when present")
        ->type_name("FILE")
        ->required();
    cmd->add_option("--radius", radius_, "score returns within this horizontal range (m)")
        ->check(CLI::Range(0.1, 1000.0));
    cmd->add_flag("--json", json_, "print JSON instead of a table");
    add_frames_option(*cmd, config_.max_frames);
    add_detector_options(*cmd, config_);
    add_log_level_option(*cmd, log_level_);
    extrinsics_ = cmd->get_option("--extrinsics");
  }

  int run() override {
    const std::filesystem::path pcap_path = pcap_path_;
    apply_log_level(log_level_);
    check_input_file("capture", pcap_path_);
    check_input_file("--labels", labels_path_);
    if (!config_.decoder.calibration_file.empty()) {
      check_input_file("--calibration", config_.decoder.calibration_file);
    }
    PipelineConfig& config = config_;
    const double radius = radius_;
    PcapSourceConfig pcap;
    pcap.path = pcap_path.string();
    const CaptureProbe probe = probe_capture(pcap, 0);
    if (!probe.error.empty()) {
      std::fprintf(stderr, "vlpground eval: %s\n", probe.error.c_str());
      return kExitFailure;
    }
    if (!probe.is_vlp16()) {
      std::fprintf(stderr, "vlpground eval: %s: no VLP-16 packets (%s)\n", pcap.path.c_str(),
                   probe.verdict().c_str());
      return kExitFailure;
    }
    const auto sim_json = std::filesystem::path(pcap_path).replace_extension(".json");
    eval::check_labels_match(probe.counters, labels_path_, sim_json);
    if (extrinsics_->count() == 0 && std::filesystem::exists(sim_json)) {
      config.detector.extrinsics = eval::load_sim_extrinsics(sim_json);
    }
    eval::CaptureScoreOptions options;
    options.score.radius_m = radius;
    options.max_frames = static_cast<int>(config.max_frames);
    const eval::CaptureScore result =
        eval::score_capture(pcap_path, labels_path_, config.detector, options);
    const eval::Confusion& c = result.score.all;
    if (json_) {
      nlohmann::json j = {
          {"capture", result.capture},
          {"method", result.method},
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
          {"high_obstacles", result.score.high_obstacles},
          {"high_obstacles_as_ground", result.score.high_obstacles_as_ground},
          {"high_obstacle_terrain", std::string(eval::to_string(result.score.terrain_source()))},
      };
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("%-10s %s\n%-10s %s\n%-10s %llu\n%-10s %.1f m\n", "capture",
                  result.capture.c_str(), "method", result.method.c_str(), "frames",
                  static_cast<unsigned long long>(result.score.frames), "radius", radius);
      std::printf("%-10s %.4f\n%-10s %.4f\n%-10s %.4f\n", "precision", c.precision(), "recall",
                  c.recall(), "F1", c.f1());
      std::printf("%-10s tp %llu, fp %llu, fn %llu, tn %llu\n", "counts",
                  static_cast<unsigned long long>(c.tp), static_cast<unsigned long long>(c.fp),
                  static_cast<unsigned long long>(c.fn), static_cast<unsigned long long>(c.tn));
      print_high_obstacles(result.score);
    }
    return kExitOk;
  }

 private:
  // Obstacles more than 0.5 m above the terrain labelled ground, and how the terrain was known.
  void print_high_obstacles(const eval::Score& score) const {
    std::printf("%-10s %llu of %llu labelled ground (%.4f)\n", "high obst.",
                static_cast<unsigned long long>(score.high_obstacles_as_ground),
                static_cast<unsigned long long>(score.high_obstacles),
                score.high_obstacle_as_ground_rate());
    switch (score.terrain_source()) {
      case eval::TerrainSource::exact:
        std::printf("%-10s exact heights from %s\n", "terrain",
                    eval::heights_path_beside(labels_path_).string().c_str());
        break;
      case eval::TerrainSource::estimated:
        std::printf("%-10s estimated from the truth-ground returns (no %s)\n", "terrain",
                    eval::heights_path_beside(labels_path_).string().c_str());
        break;
      default:
        std::printf("%-10s %s\n", "terrain",
                    std::string(eval::to_string(score.terrain_source())).c_str());
    }
  }

  std::string pcap_path_, labels_path_;
  double radius_ = eval::ScoreConfig{}.radius_m;
  bool json_ = false;
  std::string log_level_ = "warn";
  PipelineConfig config_;
  CLI::Option* extrinsics_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> add_eval_command(CLI::App& app) {
  return std::make_unique<EvalCommand>(app);
}

}  // namespace vlpground::cli
