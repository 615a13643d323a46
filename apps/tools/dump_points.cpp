// Developer tool (not installed): one CSV row per return of a labelled capture, in the
// vehicle frame (the capture's STEM.json mounting as extrinsics), with its truth byte, its
// exact height above the terrain (column `above`, from the .heights beside the labels; empty
// without one) and the detector's label, for looking at where a method fails
// (docs/detector.md).
//
//   vlpground_dump_points CAPTURE.pcap LABELS OUT.csv [profiles|cells|paper]
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "vlpground/evaluation/evaluation.hpp"

namespace fs = std::filesystem;
using namespace vlpground;

namespace {

// The `above` column: the slot's exact height above the terrain (m), empty when unknown.
std::string above_cell(const eval::GroundTruth& truth, const eval::SlotRef& s) {
  const auto above = truth.height_above_terrain_m(s.packet, s.slot());
  if (!above) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", static_cast<double>(*above));
  return text;
}

void write_frame(std::FILE* out, int number, const Frame& f, const GroundResult& r,
                 const eval::GroundTruth& truth, const RigidTransform& tf) {
  for (int layer = 0; layer < f.layers(); ++layer) {
    const ReturnLayer& ret = f.layer[layer];
    for (int ring = 0; ring < kLasers; ++ring) {
      for (int col = 0; col < f.columns(); ++col) {
        const std::size_t cell = f.index(ring, col);
        if (f.column_valid[static_cast<std::size_t>(col)] == 0 || ret.valid[cell] == 0) continue;
        if (layer == kLastLayer && f.same_echo[cell] != 0) continue;
        const eval::SlotRef s = eval::slot_of_cell(f, ring, col, layer);
        const float p[3] = {ret.x_m[cell], ret.y_m[cell], ret.z_m[cell]};
        float v[3];
        for (int k = 0; k < 3; ++k)
          v[k] = tf.r[k][0] * p[0] + tf.r[k][1] * p[1] + tf.r[k][2] * p[2] + tf.t[k];
        const std::size_t o = static_cast<std::size_t>(ring) * static_cast<std::size_t>(r.stride) +
                              static_cast<std::size_t>(col);
        std::fprintf(out, "%d,%d,%d,%d,%.3f,%.3f,%.3f,%d,%d,%.3f,%s\n", number, ring, col, layer,
                     v[0], v[1], v[2], static_cast<int>(truth.at(s.packet, s.slot())),
                     static_cast<int>(r.label[layer][o]), static_cast<double>(r.height_m[layer][o]),
                     above_cell(truth, s).c_str());
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    std::fprintf(stderr, "usage: %s CAPTURE.pcap LABELS OUT.csv [profiles|cells|paper]\n", argv[0]);
    return 2;
  }
  try {
    DetectorConfig c;
    const fs::path pcap = argv[1];
    fs::path json = pcap;
    json.replace_extension(".json");
    if (fs::exists(json)) c.extrinsics = eval::load_sim_extrinsics(json);
    const std::string mode = argc == 5 ? argv[4] : "profiles";
    if (mode != "profiles" && mode != "cells" && mode != "paper") {
      std::fprintf(stderr, "unknown mode '%s'\n", mode.c_str());
      return 2;
    }
    c.terrain_refinement = mode != "paper";
    c.column_profiles = mode == "profiles";
    const RigidTransform tf = vehicle_from_sensor(c.extrinsics);
    const eval::GroundTruth truth = eval::GroundTruth::load_with_heights(argv[2]);
    std::FILE* out = std::fopen(argv[3], "w");
    if (out == nullptr) {
      std::fprintf(stderr, "cannot write '%s'\n", argv[3]);
      return 1;
    }
    std::fprintf(out, "frame,ring,col,layer,x,y,z,truth,pred,h,above\n");
    eval::CaptureScoreOptions options;
    int number = 0;
    options.on_frame = [&](std::size_t, const Frame& f, const GroundResult& r, const eval::Score&) {
      write_frame(out, number++, f, r, truth, tf);
    };
    const eval::CaptureScore s = eval::score_capture(pcap, argv[2], c, options);
    const bool ok = std::fclose(out) == 0;
    std::printf("F1 %.4f over %d frames\n", s.score.all.f1(), number);
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
