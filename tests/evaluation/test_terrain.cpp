// Issue 10 on a CI-sized slice of the evaluation set (scripts/make_eval_set.sh makes the
// full one): every simulator scene kind at one tuning seed (1) and one held-out seed (101),
// strongest and dual, 2 frames, made in-process by the simulator. The default method (the
// paper's with terrain refinement and column profiles) against the cells alone
// (column_profiles = false) and the paper's alone (terrain_refinement = false).
// Floors are the minima measured when they were set (docs/accuracy.md) less 0.01; where
// the targets (F1 >= 0.98, high obstacles <= 0.5 %) are not met yet, the floor says
// what is, and docs/detector.md lists the gap.
#include <catch2/catch.hpp>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "test_data.hpp"
#include "vlpground/evaluation/evaluation.hpp"
#include "vlpground/sim/capture_writer.hpp"
#include "vlpground/sim/simulator.hpp"

namespace {

namespace fs = std::filesystem;
using vlpground::DetectorConfig;
using vlpground::sim::SceneKind;

struct Result {
  vlpground::eval::Score refined, cells, paper;
  std::vector<double> near_recall;  // per frame: truth ground within 10 m labelled ground
};

fs::path make_capture(const fs::path& dir, SceneKind kind, std::uint64_t seed,
                      vlpground::ReturnMode mode) {
  vlpground::sim::SimConfig c;
  c.scene = kind;
  c.seed = seed;
  c.frames = 2;
  c.mode = mode;
  const vlpground::sim::Simulator sim(c);
  const fs::path stem =
      dir / (std::string(vlpground::sim::to_string(kind)) + "_" + std::to_string(seed) +
             (mode == vlpground::ReturnMode::dual ? "_dual" : ""));
  vlpground::sim::write_capture(sim, stem);
  return stem;
}

Result evaluate(const fs::path& stem) {
  fs::path pcap = stem, labels = stem, json = stem;
  pcap += ".pcap";
  labels += ".labels";
  json += ".json";
  std::vector<DetectorConfig> configs(3);
  configs[1].column_profiles = false;
  configs[2].column_profiles = false;
  configs[2].terrain_refinement = false;
  for (auto& c : configs) c.extrinsics = vlpground::eval::load_sim_extrinsics(json);
  vlpground::eval::CaptureScoreOptions options;
  const auto scores = vlpground::eval::score_capture(pcap, labels, configs, options);
  Result r{scores[0].score, scores[1].score, scores[2].score, {}};
  // The road under the vehicle: recall of truth ground within 10 m, frame by frame.
  vlpground::eval::CaptureScoreOptions near;
  near.score.radius_m = 10.0;
  near.on_frame = [&](std::size_t, const vlpground::Frame&, const vlpground::GroundResult&,
                      const vlpground::eval::Score& s) {
    if (s.all.tp + s.all.fn > 100) r.near_recall.push_back(s.all.recall());
  };
  vlpground::eval::score_capture(pcap, labels, configs[0], near);
  return r;
}

const std::map<std::string, Result>& results() {
  static const std::map<std::string, Result> all = [] {
    std::map<std::string, Result> out;
    const fs::path dir = vlpground::test::temp_dir("terrain_eval");
    for (int k = 0; k <= static_cast<int>(SceneKind::garage); ++k) {
      for (const std::uint64_t seed : {1u, 101u}) {
        for (const auto mode : {vlpground::ReturnMode::strongest, vlpground::ReturnMode::dual}) {
          const fs::path stem = make_capture(dir, static_cast<SceneKind>(k), seed, mode);
          out.emplace(stem.filename().string(), evaluate(stem));
        }
      }
    }
    fs::remove_all(dir);
    return out;
  }();
  return all;
}

std::string kind_of(const std::string& name) { return name.substr(0, name.find('_')); }

// Minimum F1 of the default method per kind on this slice, less 0.01 (measured at the
// revision that set them; see docs/accuracy.md for the full set). The 0.98 holds on
// every capture of this slice; the full evaluation set has harder ones (docs/detector.md).
const std::map<std::string, double> kFloor = {
    {"flat", 0.98}, {"urban", 0.98},  {"slope", 0.98},      {"hills", 0.975},
    {"jam", 0.98},  {"fences", 0.97}, {"embankment", 0.97}, {"bank", 0.97},
    {"bowl", 0.98}, {"crest", 0.98},  {"garage", 0.97},
};

// Obstacles more than 0.5 m above the terrain labelled ground, judged by the exact heights the
// simulator writes beside the labels: the 0.5 % holds on every kind of this slice but
// three; there the limit is what was measured, rounded up (docs/detector.md, "High obstacles
// against the exact terrain"): crest_101 1.26 % (0.0 % against the estimated terrain, which
// hid it), bank_1_dual 0.90 % (1.14 % against the estimate), fences_101 0.60 %.
const std::map<std::string, double> kHighLimit = {
    {"fences", 0.01}, {"bank", 0.012}, {"crest", 0.015}};

}  // namespace

// One test case (ctest runs each in its own process): the slice is simulated and scored once.
TEST_CASE("terrain refinement on the evaluation slice", "[evaluation][terrain]") {
  SECTION("F1 per scene kind on tuning and held-out seeds") {
    for (const auto& [name, r] : results()) {
      INFO(name << ": refined F1 " << r.refined.all.f1() << ", paper only " << r.paper.all.f1());
      CHECK(r.refined.all.f1() >= kFloor.at(kind_of(name)));
    }
  }
  SECTION("rolling and curved terrain gain over the paper's method") {
    for (const auto& [name, r] : results()) {
      const std::string kind = kind_of(name);
      INFO(name << ": default F1 " << r.refined.all.f1() << ", paper only " << r.paper.all.f1());
      if (kind == "hills" || kind == "bowl" || kind == "embankment" || kind == "bank")
        CHECK(r.refined.all.f1() >= r.paper.all.f1() + 0.02);
      else  // fences at seed 101 lose 0.010 (single ring lines on low fences; docs/detector.md)
        CHECK(r.refined.all.f1() >= r.paper.all.f1() - 0.012);
    }
  }
  SECTION("column profiles gain over the cells alone") {
    for (const auto& [name, r] : results()) {
      const std::string kind = kind_of(name);
      INFO(name << ": default F1 " << r.refined.all.f1() << ", cells only " << r.cells.all.f1());
      if (kind == "bank") CHECK(r.refined.all.f1() >= r.cells.all.f1() + 0.03);
      if (kind == "bank" || kind == "garage" || kind == "embankment" || kind == "hills" ||
          kind == "bowl")
        CHECK(r.refined.all.f1() > r.cells.all.f1());
      else
        CHECK(r.refined.all.f1() >= r.cells.all.f1() - 0.012);
    }
  }
  SECTION("tall obstacles stay obstacles") {
    for (const auto& [name, r] : results()) {
      const auto limit = kHighLimit.find(kind_of(name));
      INFO(name << ": high obstacles as ground " << r.refined.high_obstacle_as_ground_rate());
      CHECK(r.refined.high_obstacle_as_ground_rate() <=
            (limit == kHighLimit.end() ? 0.005 : limit->second));
    }
  }
  SECTION("embankment: the road under the vehicle is ground in every frame") {
    for (const auto& [name, r] : results()) {
      if (kind_of(name) != "embankment") continue;
      INFO(name);
      REQUIRE_FALSE(r.near_recall.empty());
      for (const double recall : r.near_recall) CHECK(recall >= 0.995);
    }
  }
}

// A fence line met by one ring past level ground, the ring below on the ground in front of
// it, is no bend of the terrain (climbs_object_line): fences_s704, whose level-2 cells 22-26 m
// out climbed such lines (0.77 % of its high obstacles labelled ground over these 2 frames
// before the check, 0.05 % with it).
TEST_CASE("a fence line past level ground is no bend (fences_s704)", "[evaluation][terrain]") {
  const fs::path dir = vlpground::test::temp_dir("terrain_fence_line");
  const fs::path stem = make_capture(dir, SceneKind::fences, 704, vlpground::ReturnMode::strongest);
  const Result r = evaluate(stem);
  fs::remove_all(dir);
  INFO("high obstacles as ground " << r.refined.high_obstacle_as_ground_rate());
  CHECK(r.refined.high_obstacle_as_ground_rate() <= 0.002);
  CHECK(r.refined.all.f1() >= 0.995);
}
