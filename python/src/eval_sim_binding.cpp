// vlpground.evaluate (the evaluation library, as `vlpground eval`) and vlpground.simulate.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "conversions.hpp"
#include "vlpground/evaluation/evaluation.hpp"
#include "vlpground/sim/capture_writer.hpp"
#include "vlpground/sim/simulator.hpp"

namespace vlpground::python {
namespace {

using py::literals::operator""_a;
namespace fs = std::filesystem;

// Counters of a whole pass over a capture's packets (no decoding).
SourceCounters count_packets(const fs::path& pcap) {
  PcapSourceConfig config;
  config.path = pcap.string();
  const auto source = open_pcap_source(config);
  PacketView view;
  while (source->next(view, -1) == SourceStatus::packet) {
  }
  return source->counters();
}

// The figures of `vlpground eval --json`, same names, after the same checks.
py::dict evaluate(const fs::path& pcap, const fs::path& labels, DetectorConfig detector,
                  bool extrinsics_given, double radius_m, int max_frames) {
  if (!(radius_m > 0)) throw py::value_error("radius_m must be > 0");
  if (max_frames < 0) throw py::value_error("max_frames must be >= 0");
  // As the CLI: a simulator capture's mounting pose comes from STEM.json unless given.
  const fs::path sim_json = fs::path(pcap).replace_extension(".json");
  {
    py::gil_scoped_release release;
    eval::check_labels_match(count_packets(pcap), labels, sim_json);
  }
  if (!extrinsics_given && fs::exists(sim_json)) {
    detector.extrinsics = eval::load_sim_extrinsics(sim_json);
  }
  eval::CaptureScoreOptions options;
  options.score.radius_m = radius_m;
  options.max_frames = max_frames;
  eval::CaptureScore result;
  {
    py::gil_scoped_release release;
    result = eval::score_capture(pcap, labels, detector, options);
  }
  if (result.score.frames == 0) {
    throw std::runtime_error(pcap.string() + ": no VLP-16 frame decoded, nothing to evaluate");
  }
  const eval::Confusion& c = result.score.all;
  return py::dict(
      "capture"_a = result.capture, "method"_a = result.method, "radius_m"_a = radius_m,
      "frames"_a = result.score.frames, "precision"_a = c.precision(), "recall"_a = c.recall(),
      "f1"_a = c.f1(), "tp"_a = c.tp, "fp"_a = c.fp, "fn"_a = c.fn, "tn"_a = c.tn,
      "detect_ms_total"_a = result.detect_ms_total,
      "high_obstacle_as_ground_rate"_a = result.score.high_obstacle_as_ground_rate(),
      "high_obstacles"_a = result.score.high_obstacles,
      "high_obstacles_as_ground"_a = result.score.high_obstacles_as_ground,
      "high_obstacle_terrain"_a = std::string(eval::to_string(result.score.terrain_source())));
}

py::dict simulate(const std::string& scene, const fs::path& out, std::uint64_t seed, int frames,
                  double rpm, const std::string& mode, const std::string& model,
                  std::optional<double> sensor_height_m, std::optional<double> speed_mps,
                  double roll_deg, double pitch_deg) {
  sim::SimConfig config;
  const auto kind = sim::parse_scene_kind(scene);
  if (!kind) {
    throw py::value_error("unknown scene '" + scene + "' (" +
                          std::string(sim::scene_kind_list()) + ")");
  }
  config.scene = *kind;
  config.seed = seed;
  config.frames = frames;
  config.rpm = rpm;
  config.mode = parse_mode(mode);
  config.model = parse_model(model);
  config.sensor_height_m = sensor_height_m;
  config.speed_mps = speed_mps;
  config.mount_roll_deg = roll_deg;
  config.mount_pitch_deg = pitch_deg;
  sim::CaptureSummary summary;
  {
    py::gil_scoped_release release;
    const sim::Simulator simulator(config);
    if (out.has_parent_path()) fs::create_directories(out.parent_path());
    summary = sim::write_capture(simulator, out);
  }
  const auto with_ext = [&out](const char* ext) { return fs::path(out).concat(ext); };
  return py::dict("pcap"_a = with_ext(".pcap"), "labels"_a = with_ext(".labels"),
                  "heights"_a = eval::heights_path_beside(with_ext(".labels")),
                  "json"_a = with_ext(".json"), "data_packets"_a = summary.data_packets,
                  "position_packets"_a = summary.position_packets, "returns"_a = summary.returns,
                  "ground_returns"_a = summary.ground_returns, "duration_s"_a = summary.duration_s);
}

// Precision, recall and F1 of summed confusion counts (the library's definitions).
py::tuple confusion_scores(std::uint64_t tp, std::uint64_t fp, std::uint64_t fn, std::uint64_t tn) {
  const eval::Confusion c{tp, fp, fn, tn};
  return py::make_tuple(c.precision(), c.recall(), c.f1());
}

}  // namespace

void bind_eval_sim(py::module_& m) {
  m.def("_evaluate", &evaluate, "pcap"_a, "labels"_a, "detector"_a, "extrinsics_given"_a,
        "radius_m"_a, "max_frames"_a);
  m.def("_simulate", &simulate, "scene"_a, "out"_a, "seed"_a, "frames"_a, "rpm"_a, "mode"_a,
        "model"_a, "sensor_height_m"_a, "speed_mps"_a, "roll_deg"_a, "pitch_deg"_a);
  m.def("_confusion_scores", &confusion_scores, "tp"_a, "fp"_a, "fn"_a, "tn"_a);
  m.def("sim_extrinsics", &eval::load_sim_extrinsics, "json_path"_a,
        "Extrinsics of a simulator capture from its STEM.json (mounting roll/pitch, sensor "
        "height), so the vehicle frame has z = 0 on the ground under the sensor.");
  m.attr("SCENES") = py::str(std::string(sim::scene_kind_list())).attr("split")("|");
}

}  // namespace vlpground::python
