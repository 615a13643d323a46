// Regenerates docs/accuracy.md: scores every labelled capture of a folder with every method.
//
//   vlpground_accuracy_table [SIM_DIR] [--frames N] > docs/accuracy.md
//
// SIM_DIR defaults to ../shared/data/sim relative to the working directory's parent layout
// used by the project (pass it explicitly when in doubt).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "vlpground/evaluation/evaluation.hpp"

namespace {

namespace fs = std::filesystem;
using vlpground::eval::CaptureScore;

std::vector<fs::path> labelled_captures(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const fs::path& p = entry.path();
    if (p.extension() != ".pcap") continue;
    fs::path labels = p;
    labels.replace_extension(".labels");
    if (fs::exists(labels)) out.push_back(p);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void print_row(const CaptureScore& s) {
  const auto& c = s.score.all;
  std::printf("| %s | %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %llu | %.1f |\n",
              s.capture.c_str(), s.method.c_str(), c.precision(), c.recall(), c.f1(),
              s.score.near_band.f1(), s.score.far_band.f1(), s.score.high_obstacle_as_ground_rate(),
              static_cast<unsigned long long>(s.score.high_obstacles),
              s.score.frames == 0 ? 0.0 : s.detect_ms_total / static_cast<double>(s.score.frames));
}

}  // namespace

int main(int argc, char** argv) {
  fs::path dir = "../shared/data/sim";
  int frames = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--frames" && i + 1 < argc) {
      frames = std::atoi(argv[++i]);
    } else if (arg == "-h" || arg == "--help") {
      std::printf("usage: vlpground_accuracy_table [SIM_DIR] [--frames N] > docs/accuracy.md\n");
      return 0;
    } else {
      dir = arg;
    }
  }
  try {
    const auto captures = labelled_captures(dir);
    if (captures.empty()) {
      std::fprintf(stderr, "no labelled captures (*.pcap + *.labels) in %s\n", dir.c_str());
      return 1;
    }
    std::printf(
        "| capture | method | precision | recall | F1 | F1 0-20 m | F1 20-40 m | "
        "high obstacles as ground | high obstacles | detect ms/frame |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& pcap : captures) {
      fs::path labels = pcap, json = pcap;
      labels.replace_extension(".labels");
      json.replace_extension(".json");
      for (const char* method : {"tangent", "ransac", "lpr"}) {
        vlpground::DetectorConfig config;
        config.method = method;
        if (fs::exists(json)) config.extrinsics = vlpground::eval::load_sim_extrinsics(json);
        vlpground::eval::CaptureScoreOptions options;
        options.max_frames = frames;
        print_row(vlpground::eval::score_capture(pcap, labels, config, options));
        std::fflush(stdout);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground_accuracy_table: %s\n", e.what());
    return 1;
  }
  return 0;
}
