// The simulator's exact heights through score_capture: a bank capture (bushes on a steep cut
// slope) scored with its STEM.heights and with the labels alone (the terrain estimated).
// Only the high-obstacle figures may differ.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "test_data.hpp"
#include "vlpground/evaluation/evaluation.hpp"
#include "vlpground/sim/capture_writer.hpp"
#include "vlpground/sim/simulator.hpp"

namespace {

namespace fs = std::filesystem;

fs::path with_ext(const fs::path& stem, const char* ext) { return fs::path(stem).concat(ext); }

}  // namespace

TEST_CASE("score_capture uses the heights beside the labels, and only for high obstacles",
          "[evaluation][sim]") {
  vlpground::sim::SimConfig c;
  c.scene = vlpground::sim::SceneKind::bank;
  c.seed = 1;
  c.frames = 2;
  const fs::path dir = vlpground::test::temp_dir("eval_exact_heights");
  const fs::path stem = dir / "bank";
  vlpground::sim::write_capture(vlpground::sim::Simulator(c), stem);
  // The same labels without a heights file beside them.
  fs::create_directories(dir / "labels_only");
  const fs::path labels_only = dir / "labels_only" / "bank.labels";
  fs::copy_file(with_ext(stem, ".labels"), labels_only, fs::copy_options::overwrite_existing);

  vlpground::DetectorConfig detector;
  detector.extrinsics = vlpground::eval::load_sim_extrinsics(with_ext(stem, ".json"));
  const auto exact =
      vlpground::eval::score_capture(with_ext(stem, ".pcap"), with_ext(stem, ".labels"), detector)
          .score;
  const auto estimated =
      vlpground::eval::score_capture(with_ext(stem, ".pcap"), labels_only, detector).score;

  CHECK(exact.terrain_source() == vlpground::eval::TerrainSource::exact);
  CHECK(estimated.terrain_source() == vlpground::eval::TerrainSource::estimated);
  CHECK(exact.obstacles_exact_terrain > 1000);
  CHECK(exact.obstacles_exact_terrain ==
        estimated.obstacles_estimated_terrain + estimated.obstacles_without_terrain);
  CHECK(exact.high_obstacles > 100);
  // Precision, recall, F1: the same counts.
  CHECK(exact.all.tp == estimated.all.tp);
  CHECK(exact.all.fp == estimated.all.fp);
  CHECK(exact.all.fn == estimated.all.fn);
  CHECK(exact.all.tn == estimated.all.tn);
  CHECK(exact.frames == estimated.frames);

  // A heights file of another size is refused, naming it.
  const fs::path heights = vlpground::eval::heights_path_beside(labels_only);
  fs::copy_file(with_ext(stem, ".heights"), heights, fs::copy_options::overwrite_existing);
  fs::resize_file(heights, fs::file_size(heights) - 768);
  try {
    (void)vlpground::eval::score_capture(with_ext(stem, ".pcap"), labels_only, detector);
    FAIL("a short heights file was accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find(heights.string()) != std::string::npos);
  }
  fs::remove_all(dir);
}
