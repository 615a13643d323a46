// Built-in sensor models and the ROS-style calibration YAML.
#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "test_data.hpp"
#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/sensor_model.hpp"

namespace {

using namespace vlpground;

std::string laser_line(int id, double vert_rad, double offset_m, double rot_rad = 0.0) {
  return "  - {laser_id: " + std::to_string(id) + ", vert_correction: " + std::to_string(vert_rad) +
         ", rot_correction: " + std::to_string(rot_rad) +
         ", vert_offset_correction: " + std::to_string(offset_m) +
         ", dist_correction: 0.0, horiz_offset_correction: 0.0}\n";
}

// A valid file: VLP-16 angles, 1 cm offsets, laser 5 rotated by 0.01 rad.
std::string valid_yaml() {
  std::string s = "num_lasers: 16\ndistance_resolution: 0.002\nlasers:\n";
  const auto model = SensorModel::builtin(Model::vlp16);
  for (int id = 0; id < 16; ++id) {
    s += laser_line(id, model.lasers[static_cast<std::size_t>(id)].elevation_deg * M_PI / 180.0,
                    0.01, id == 5 ? 0.01 : 0.0);
  }
  return s;
}

std::string write(const std::string& tag, const std::string& text) {
  const auto path = test::temp_dir(tag) / "calibration.yaml";
  std::ofstream(path) << text;
  return path.string();
}

std::string rejection(const std::string& tag, const std::string& text) {
  try {
    SensorModel::from_calibration_file(write(tag, text), Model::vlp16);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("built-in models: rings sorted by elevation", "[decoder][model]") {
  for (Model m : {Model::vlp16, Model::hires}) {
    const auto model = SensorModel::builtin(m);
    for (int ring = 1; ring < 16; ++ring) {
      CHECK(model.lasers[model.laser_of_ring[static_cast<std::size_t>(ring)]].elevation_deg >
            model.lasers[model.laser_of_ring[static_cast<std::size_t>(ring - 1)]].elevation_deg);
    }
    for (int laser = 0; laser < 16; ++laser) {  // facts: even l -> l/2, odd l -> 8 + (l-1)/2
      const int expected = laser % 2 == 0 ? laser / 2 : 8 + (laser - 1) / 2;
      CHECK(model.ring_of_laser[static_cast<std::size_t>(laser)] == expected);
    }
  }
  CHECK(SensorModel::builtin(Model::hires).lasers[15].elevation_deg == Approx(10.0));
  CHECK(SensorModel::builtin(Model::vlp16).lasers[0].vertical_offset_m == Approx(0.0112));
}

TEST_CASE("calibration YAML: a good file is applied", "[decoder][model]") {
  const auto path = write("calib_good", valid_yaml());
  const auto model = SensorModel::from_calibration_file(path, Model::vlp16);
  CHECK(model.lasers[0].elevation_deg == Approx(-15.0).margin(1e-4));
  CHECK(model.lasers[3].vertical_offset_m == Approx(0.01));
  CHECK(model.lasers[5].azimuth_offset_deg == Approx(0.01 * 180.0 / M_PI).margin(1e-4));
  CHECK(model.ring_of_laser[1] == 8);
  CHECK(model.distance_resolution_m == Approx(0.002));

  DecoderConfig config;
  config.calibration_file = path;
  PacketDecoder decoder(config);
  CHECK(decoder.sensor_model(Model::vlp16).lasers[3].vertical_offset_m == Approx(0.01));
  // Frames name the calibration they were decoded with (shared, one object per decoder).
  CHECK(decoder.calibration(Model::vlp16)->source == path);
  CHECK(decoder.calibration(Model::hires) == decoder.calibration(Model::vlp16));
  CHECK(PacketDecoder().calibration(Model::hires)->source == "built-in");
}

TEST_CASE("calibration YAML: malformed files are rejected with the file and field",
          "[decoder][model]") {
  std::string e = rejection("calib_missing", "");
  CHECK(e.find("calibration.yaml") != std::string::npos);

  e = rejection("calib_syntax", "lasers: [\n  - {laser_id: 0,\n");
  CHECK(e.find("line") != std::string::npos);

  std::string text = valid_yaml();
  text.replace(text.find("laser_id: 7,"), 12, "laser_id: 6,");
  e = rejection("calib_dup", text);
  CHECK(e.find("repeated") != std::string::npos);
  CHECK(e.find("line 11") != std::string::npos);  // 3 header lines, lasers[7] on line 11

  text = valid_yaml();
  text.replace(text.find("vert_correction"), 15, "vert_korrection");
  e = rejection("calib_field", text);
  CHECK(e.find("vert_correction") != std::string::npos);
  CHECK(e.find("lasers[0]") != std::string::npos);

  text = valid_yaml();
  text.replace(text.find("vert_offset_correction: 0.010000"), 32, "vert_offset_correction: .nan");
  CHECK(rejection("calib_nan", text).find("out of range") != std::string::npos);

  text = valid_yaml();
  text.replace(text.find("num_lasers: 16"), 14, "num_lasers: 32");
  CHECK(rejection("calib_count", text).find("num_lasers") != std::string::npos);

  text = valid_yaml();
  text.erase(text.rfind("  - {"));
  CHECK(rejection("calib_15", text).find("15 entries") != std::string::npos);

  text = valid_yaml();
  text.replace(text.find("laser_id: 2,"), 12, "laser_id: x,");
  CHECK(rejection("calib_id", text).find("laser_id") != std::string::npos);

  DecoderConfig config;
  config.calibration_file = "/nonexistent/calibration.yaml";
  CHECK_THROWS_AS(config.validate(), std::invalid_argument);
}
