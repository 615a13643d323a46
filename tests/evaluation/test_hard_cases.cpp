// The paper's hard cases (issue 4), each measured where it occurs in the labelled simulator
// captures, with the default `tangent` detector and the capture's mounting as extrinsics:
// far obstacles at 28-45 m, grade changes, traffic jams with little visible ground, low
// fences. Skips without ../shared.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <string>

#include "test_data.hpp"
#include "vlpground/evaluation/evaluation.hpp"

namespace {

using vlpground::DetectorConfig;
using vlpground::Frame;
using vlpground::GroundLabel;
using vlpground::GroundResult;
using vlpground::eval::GroundTruth;
using vlpground::eval::Score;
using vlpground::eval::TruthLabel;

constexpr int kFrames = 5;

struct Inputs {
  std::filesystem::path pcap, labels;
  DetectorConfig detector;
};

// False (the test skips) when the shared captures are absent.
bool inputs_of(const std::string& stem, Inputs& out) {
  const auto pcap = vlpground::test::shared_file("sim", stem + ".pcap");
  const auto labels = vlpground::test::shared_file("sim", stem + ".labels");
  const auto json = vlpground::test::shared_file("sim", stem + ".json");
  if (!pcap || !labels || !json) return false;
  out = Inputs{*pcap, *labels, {}};
  out.detector.extrinsics = vlpground::eval::load_sim_extrinsics(*json);
  return true;
}

Score score_of(const Inputs& in) {
  vlpground::eval::CaptureScoreOptions options;
  options.max_frames = kFrames;
  return vlpground::eval::score_capture(in.pcap, in.labels, in.detector, options).score;
}

// Truth obstacles at a horizontal range in [near_m, far_m) and how many were labelled ground.
struct ObstacleCount {
  std::uint64_t obstacles = 0, as_ground = 0;
};

ObstacleCount obstacles_in_band(const Inputs& in, double near_m, double far_m) {
  const GroundTruth truth = GroundTruth::load(in.labels);
  ObstacleCount count;
  vlpground::eval::CaptureScoreOptions options;
  options.max_frames = kFrames;
  options.score.radius_m = far_m;  // score the whole band (the default stops at 40 m)
  options.on_frame = [&](std::size_t, const Frame& frame, const GroundResult& result,
                         const Score&) {
    for (int layer = 0; layer < frame.layers(); ++layer) {
      const auto& cells = frame.layer[layer];
      for (int ring = 0; ring < vlpground::kLasers; ++ring) {
        for (int col = 0; col < frame.columns(); ++col) {
          const std::size_t i = frame.index(ring, col);
          if (cells.valid[i] == 0) continue;
          const double range = std::hypot(cells.x_m[i], cells.y_m[i]);
          if (range < near_m || range >= far_m) continue;
          const auto slot = vlpground::eval::slot_of_cell(frame, ring, col, layer);
          if (truth.at(slot.packet, slot.slot()) != TruthLabel::obstacle) continue;
          ++count.obstacles;
          if (result.label[layer][i] == static_cast<std::uint8_t>(GroundLabel::ground)) {
            ++count.as_ground;
          }
        }
      }
    }
  };
  (void)vlpground::eval::score_capture(in.pcap, in.labels, in.detector, options);
  return count;
}

double obstacle_as_ground_rate(const vlpground::eval::Confusion& c) {
  return c.fp + c.tn == 0 ? 0.0 : static_cast<double>(c.fp) / static_cast<double>(c.fp + c.tn);
}

}  // namespace

TEST_CASE("hard case: far obstacles at 28-45 m stay obstacles", "[evaluation][sim][hard]") {
  ObstacleCount total;
  for (const char* stem : {"urban_strongest", "flat_strongest", "jam_strongest"}) {
    Inputs in;
    VLPGROUND_REQUIRE_SHARED(inputs_of(stem, in));
    const ObstacleCount c = obstacles_in_band(in, 28.0, 45.0);
    INFO(stem << ": " << c.as_ground << " of " << c.obstacles << " labelled ground");
    CHECK(c.as_ground <= c.obstacles / 100);
    total.obstacles += c.obstacles;
    total.as_ground += c.as_ground;
  }
  CHECK(total.obstacles > 1000);  // the band is really populated in these scenes
}

TEST_CASE("hard case: grade changes keep their ground out to 40 m", "[evaluation][sim][hard]") {
  for (const char* stem : {"slope_strongest", "slope_dual"}) {
    Inputs in;
    VLPGROUND_REQUIRE_SHARED(inputs_of(stem, in));
    const Score s = score_of(in);
    INFO(stem << ": far band precision " << s.far_band.precision() << " recall "
              << s.far_band.recall());
    CHECK(s.far_band.recall() >= 0.98);
    CHECK(s.far_band.precision() >= 0.98);
    // 0.3 % (dual) and 0.6 % (strongest) with the column profiles, 0 % with the cells alone:
    // low returns at the foot of walls on the slope (docs/detector.md, "Column profiles").
    CHECK(s.high_obstacle_as_ground_rate() <= 0.007);
  }
}

TEST_CASE("hard case: traffic jams, little visible ground, no car roof as ground",
          "[evaluation][sim][hard]") {
  for (const char* stem : {"jam_strongest", "jam_dual"}) {
    Inputs in;
    VLPGROUND_REQUIRE_SHARED(inputs_of(stem, in));
    const Score s = score_of(in);
    INFO(stem << ": precision " << s.all.precision() << ", high obstacles as ground "
              << s.high_obstacle_as_ground_rate());
    CHECK(s.all.precision() >= 0.99);
    CHECK(s.all.recall() >= 0.99);
    CHECK(s.high_obstacles > 10000);
    CHECK(s.high_obstacle_as_ground_rate() <= 0.005);
  }
}

TEST_CASE("hard case: low fences are obstacles", "[evaluation][sim][hard]") {
  for (const char* stem : {"fences_strongest", "fences_dual"}) {
    Inputs in;
    VLPGROUND_REQUIRE_SHARED(inputs_of(stem, in));
    const Score s = score_of(in);
    INFO(stem << ": obstacles labelled ground " << obstacle_as_ground_rate(s.all));
    CHECK(s.all.fp + s.all.tn > 1000);
    CHECK(obstacle_as_ground_rate(s.all) <= 0.01);
    CHECK(s.all.f1() >= 0.99);
  }
}
