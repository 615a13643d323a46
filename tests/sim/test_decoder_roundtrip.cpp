// The project's decoder reads simulated packets back to within the format's quantisation
// (2 mm range, 0.01 degree azimuth, 1 us stamps), compared with the simulator's own truth.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/sim/simulator.hpp"

using namespace vlpground;
using namespace vlpground::sim;

namespace {

double angle_diff_deg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return std::fabs(d);
}

void check_roundtrip(const SimConfig& config) {
  const Simulator sim(config);
  PacketDecoder decoder;
  auto packet = std::make_unique<SimulatedPacket>();
  auto decoded = std::make_unique<DecodedPacket>();
  const bool dual = config.mode == ReturnMode::dual;
  int compared = 0;
  for (std::uint64_t k = 0; k < 40; ++k) {
    sim.simulate_packet(k, *packet);
    REQUIRE(decoder.decode(packet->bytes, packet->capture_ns, *decoded) == DecodeStatus::ok);
    REQUIRE(decoded->column_count == (dual ? 12 : 24));
    CHECK(decoded->model == config.model);
    CHECK(std::llabs(decoded->time_ns - packet->time_ns) < 1000);
    if (k == 0) continue;  // the first packet's last block has no measured rotation rate yet
    for (int col = 0; col < decoded->column_count; ++col) {
      const std::int64_t column_time_ns = decoded->column_time_ns[static_cast<std::size_t>(col)];
      for (int laser = 0; laser < kLasers; ++laser) {
        for (int layer = 0; layer < (dual ? 2 : 1); ++layer) {
          // Wire slot of this firing: single block = col / 2; dual even block = last.
          const int block = dual ? 2 * (col / 2) + (layer == kLastLayer ? 0 : 1) : col / 2;
          const int channel = (col % 2) * 16 + laser;
          const SlotTruth& truth = packet->truth[static_cast<std::size_t>(block * 32 + channel)];
          const LaserReturn r = decoded->at(layer, col, laser);
          CHECK(std::llabs(column_time_ns + laser * kFiringIntervalNs - truth.time_ns) < 1000);
          // Block azimuth rounding (0.005) plus the rounded gap spread over the block.
          REQUIRE(angle_diff_deg(decoded->azimuth(col, laser), truth.azimuth_deg) < 0.015);
          if (truth.range_m == 0.0) {
            REQUIRE(r.distance_m == 0.f);
            continue;
          }
          REQUIRE(std::fabs(r.distance_m - truth.range_m) < 0.001 + 1e-5 * truth.range_m);
          const double tolerance = 0.002 + truth.range_m * 0.015 * 3.14159 / 180.0;
          CHECK(std::fabs(r.x_m - truth.sensor_point.x) < tolerance);
          CHECK(std::fabs(r.y_m - truth.sensor_point.y) < tolerance);
          CHECK(std::fabs(r.z_m - truth.sensor_point.z) < tolerance);
          ++compared;
        }
      }
    }
  }
  CHECK(compared > 1000);
}

}  // namespace

TEST_CASE("decoder reads simulated single-return packets back", "[sim][decoder]") {
  SimConfig c;
  c.scene = SceneKind::urban;
  c.seed = 5;
  c.frames = 1;
  check_roundtrip(c);
  c.rpm = 1200;
  c.model = Model::hires;
  c.mode = ReturnMode::last;
  check_roundtrip(c);
}

TEST_CASE("decoder reads simulated dual-return packets back", "[sim][decoder]") {
  SimConfig c;
  c.scene = SceneKind::hills;
  c.seed = 9;
  c.frames = 1;
  c.rpm = 300;
  c.mode = ReturnMode::dual;
  check_roundtrip(c);
}
