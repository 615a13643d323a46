#include <catch2/catch.hpp>
#include <stdexcept>

#include "test_frames.hpp"
#include "vlpground/evaluation/evaluation.hpp"

using vlpground::GroundLabel;
using vlpground::eval::FrameScorer;
using vlpground::eval::ScoreConfig;
using vlpground::eval::TerrainSource;
using vlpground::eval::TruthLabel;
using vlpground::test::LabelledScene;

TEST_CASE("scorer counts the confusion matrix by range band", "[evaluation]") {
  LabelledScene s;
  s.add(5, 0, -1.8f, TruthLabel::ground, GroundLabel::ground);         // TP, near
  s.add(0, 25, -1.8f, TruthLabel::ground, GroundLabel::obstacle);      // FN, far
  s.add(-10, 0, -1.0f, TruthLabel::obstacle, GroundLabel::ground);     // FP, near
  s.add(0, -30, -1.0f, TruthLabel::obstacle, GroundLabel::obstacle);   // TN, far
  s.add(30, 30, -1.8f, TruthLabel::ground, GroundLabel::obstacle);     // 42 m: not scored
  s.add(3, 3, -1.8f, TruthLabel::ambiguous, GroundLabel::ground);      // left out
  s.add(4, 4, -1.8f, TruthLabel::none, GroundLabel::ground);           // return, no truth
  s.add(6, 6, -1.8f, TruthLabel::ground, GroundLabel::ground, false);  // truth, no return
  s.add(7, 7, -1.8f, TruthLabel::none, GroundLabel::ground, false);    // neither: fine

  FrameScorer scorer;
  const auto score = scorer.score(s.frame, s.result, s.truth());
  CHECK(score.all.tp == 1);
  CHECK(score.all.fn == 1);
  CHECK(score.all.fp == 1);
  CHECK(score.all.tn == 1);
  CHECK(score.near_band.tp == 1);
  CHECK(score.near_band.fp == 1);
  CHECK(score.near_band.total() == 2);
  CHECK(score.far_band.fn == 1);
  CHECK(score.far_band.tn == 1);
  CHECK(score.ambiguous_skipped == 1);
  CHECK(score.returns_without_truth == 1);
  CHECK(score.truth_without_return == 1);
  CHECK(score.frames == 1);
  CHECK(score.all.precision() == Approx(0.5));
  CHECK(score.all.recall() == Approx(0.5));
  CHECK(score.all.f1() == Approx(0.5));
}

TEST_CASE("precision, recall and F1 follow their definitions", "[evaluation]") {
  vlpground::eval::Confusion c;
  CHECK(c.f1() == 0.0);  // empty: defined as 0, not NaN
  c.tp = 6;
  c.fp = 2;
  c.fn = 4;
  c.tn = 100;
  CHECK(c.precision() == Approx(0.75));
  CHECK(c.recall() == Approx(0.6));
  CHECK(c.f1() == Approx(2 * 0.75 * 0.6 / (0.75 + 0.6)));
  vlpground::eval::Confusion sum = c;
  sum += c;
  CHECK(sum.total() == 2 * c.total());
  CHECK(sum.f1() == Approx(c.f1()));
}

TEST_CASE("high obstacles are measured against nearby truth ground", "[evaluation]") {
  LabelledScene s;
  // Terrain near (10, 0) at z = -1.8 (median of five, one outlier low).
  for (float dy : {-1.0f, -0.5f, 0.0f, 0.5f}) {
    s.add(10, dy, -1.8f, TruthLabel::ground, GroundLabel::ground);
  }
  s.add(10, 1.0f, -3.0f, TruthLabel::ground, GroundLabel::ground);
  s.add(10.5f, 0, -1.0f, TruthLabel::obstacle, GroundLabel::ground);       // 0.8 m up, as ground
  s.add(10.5f, 0.5f, -0.5f, TruthLabel::obstacle, GroundLabel::obstacle);  // 1.3 m up, right
  s.add(9.5f, 0, -1.5f, TruthLabel::obstacle, GroundLabel::ground);        // 0.3 m up: not high
  // No ground within 2.5 m, but ground further along the same direction: sector fallback.
  s.add(-20, -0.1f, -2.5f, TruthLabel::ground, GroundLabel::ground);
  s.add(-30, 0, -1.9f, TruthLabel::obstacle, GroundLabel::ground);  // 0.6 m above -2.5
  // Nothing in its sector at all.
  s.add(0, -30, -1.0f, TruthLabel::obstacle, GroundLabel::ground);

  FrameScorer scorer;
  const auto score = scorer.score(s.frame, s.result, s.truth());
  CHECK(score.high_obstacles == 3);
  CHECK(score.high_obstacles_as_ground == 2);
  CHECK(score.obstacles_without_terrain == 1);
  CHECK(score.high_obstacle_as_ground_rate() == Approx(2.0 / 3.0));
  CHECK(score.obstacles_estimated_terrain == 4);
  CHECK(score.obstacles_exact_terrain == 0);
  CHECK(score.terrain_source() == TerrainSource::estimated);
}

// A bush on a steep cut slope (1:2, rising along +x): the truth ground near it lies mostly
// down the slope, so the estimated terrain is too low under some returns and too high under
// others; the exact heights decide alone, strictly above 0.5 m.
TEST_CASE("high obstacles use the exact heights when the truth has them", "[evaluation]") {
  LabelledScene s;
  for (float x : {8.6f, 8.8f, 9.0f, 9.2f, 9.4f}) {  // lower slope: z = -1.8 + 0.5 (x - 10)
    s.add(x, 0, -1.8f + 0.5f * (x - 10.0f), TruthLabel::ground, GroundLabel::ground);
  }
  // Median of those: -2.3. Each obstacle: estimated height, exact height (cm), prediction.
  s.add(10.0f, 0.0f, -1.6f, TruthLabel::obstacle, GroundLabel::ground, true, 30);    // 0.7 / 0.30
  s.add(10.0f, 0.3f, -2.0f, TruthLabel::obstacle, GroundLabel::obstacle, true, 70);  // 0.3 / 0.70
  s.add(10.0f, 0.6f, -2.0f, TruthLabel::obstacle, GroundLabel::ground, true, 50);    // 0.3 / 0.50
  s.add(10.0f, 0.9f, -2.0f, TruthLabel::obstacle, GroundLabel::ground, true, 51);    // 0.3 / 0.51
  s.add(0.0f, -30.0f, -1.0f, TruthLabel::obstacle, GroundLabel::ground, true,
        80);  // no ground near

  FrameScorer scorer;
  const auto estimated = scorer.score(s.frame, s.result, s.truth());
  CHECK(estimated.high_obstacles == 1);  // the first, wrongly: 0.30 m above its slope
  CHECK(estimated.high_obstacles_as_ground == 1);
  CHECK(estimated.obstacles_estimated_terrain == 4);
  CHECK(estimated.obstacles_without_terrain == 1);
  CHECK(estimated.terrain_source() == TerrainSource::estimated);

  const auto exact = scorer.score(s.frame, s.result, s.truth_with_heights());
  CHECK(exact.high_obstacles == 3);  // 0.70, 0.51 and the one with no ground near (0.80)
  CHECK(exact.high_obstacles_as_ground == 2);
  CHECK(exact.obstacles_exact_terrain == 5);
  CHECK(exact.obstacles_estimated_terrain == 0);
  CHECK(exact.obstacles_without_terrain == 0);
  CHECK(exact.terrain_source() == TerrainSource::exact);
  // Only the high-obstacle figures change.
  CHECK(exact.all.tp == estimated.all.tp);
  CHECK(exact.all.fp == estimated.all.fp);
  CHECK(exact.all.fn == estimated.all.fn);
  CHECK(exact.all.tn == estimated.all.tn);

  vlpground::eval::Score sum = exact;
  sum += estimated;
  CHECK(sum.terrain_source() == TerrainSource::mixed);
  CHECK(vlpground::eval::Score{}.terrain_source() == TerrainSource::none);
  CHECK(to_string(TerrainSource::exact) == "exact");
  CHECK(to_string(TerrainSource::estimated) == "estimated");
}

TEST_CASE("dual frames score both layers once per echo", "[evaluation]") {
  LabelledScene s;
  s.frame.meta.mode = vlpground::ReturnMode::dual;
  const int col = s.frame.append_column();
  s.frame.column_valid[0] = 1;
  s.frame.column_packet_index[0] = 0;
  s.frame.column_in_packet[0] = 3;                 // pair 1: last in block 2, strongest in block 3
  const std::size_t cell = s.frame.index(4, col);  // ring 4 = laser 8, channel 16 + 8
  for (int l = 0; l < 2; ++l) {
    s.frame.layer[l].valid[cell] = 1;
    s.frame.layer[l].x_m[cell] = 8.0f + static_cast<float>(l);
  }
  s.truth_bytes[3 * 32 + 24] = static_cast<std::uint8_t>(TruthLabel::obstacle);  // strongest
  s.truth_bytes[2 * 32 + 24] = static_cast<std::uint8_t>(TruthLabel::ground);    // last
  s.result.label[0][cell] = static_cast<std::uint8_t>(GroundLabel::obstacle);
  s.result.label[1][cell] = static_cast<std::uint8_t>(GroundLabel::ground);

  FrameScorer scorer;
  auto score = scorer.score(s.frame, s.result, s.truth());
  CHECK(score.all.tn == 1);
  CHECK(score.all.tp == 1);
  CHECK(score.all.total() == 2);
  CHECK(score.returns_without_truth == 0);

  s.frame.same_echo[cell] = 1;  // the last return repeats the strongest: count it once
  score = scorer.score(s.frame, s.result, s.truth());
  CHECK(score.all.total() == 1);
  CHECK(score.all.tn == 1);
}

TEST_CASE("score configuration and result size are validated", "[evaluation]") {
  ScoreConfig bad;
  bad.radius_m = 0;
  CHECK_THROWS_AS(FrameScorer(bad), std::invalid_argument);
  bad = {};
  bad.terrain_radius_m = -1;
  CHECK_THROWS_AS(bad.validate(), std::invalid_argument);

  LabelledScene s;
  s.add(5, 0, -1.8f, TruthLabel::ground, GroundLabel::ground);
  s.result.label[0].clear();
  FrameScorer scorer;
  CHECK_THROWS_AS(scorer.score(s.frame, s.result, s.truth()), std::invalid_argument);
}
