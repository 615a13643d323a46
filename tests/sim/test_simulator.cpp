// Simulator packets: timing, labels vs truth, dual-return layout, determinism, position packets.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "vlpground/sim/simulator.hpp"

using namespace vlpground;
using namespace vlpground::sim;

namespace {

unsigned distance_at(const SimulatedPacket& p, int block, int channel) {
  const std::uint8_t* r = p.bytes.data() + 100 * block + 4 + 3 * channel;
  return r[0] | (unsigned{r[1]} << 8);
}
std::uint32_t le32(const std::uint8_t* p) {
  return p[0] | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

SimConfig config_for(SceneKind kind, ReturnMode mode = ReturnMode::strongest, int frames = 1) {
  SimConfig c;
  c.scene = kind;
  c.seed = 11;
  c.frames = frames;
  c.mode = mode;
  return c;
}

}  // namespace

TEST_CASE("stamps advance by 1327.104 us (single) and 663.552 us (dual)", "[sim]") {
  for (const auto mode : {ReturnMode::strongest, ReturnMode::dual}) {
    const Simulator sim(config_for(SceneKind::flat, mode));
    const double period_us = mode == ReturnMode::dual ? 663.552 : 1327.104;
    auto p = std::make_unique<SimulatedPacket>();
    sim.simulate_packet(0, *p);
    const std::uint32_t first = le32(p->bytes.data() + 1200);
    CHECK(first == 1'000'000u);  // 22:00:01 is one second past the hour
    for (std::uint64_t k : {1u, 2u, 7u, 100u}) {
      sim.simulate_packet(k, *p);
      const auto expected = static_cast<std::uint32_t>(std::floor(1e6 + period_us * double(k)));
      CHECK(le32(p->bytes.data() + 1200) == expected);
      CHECK(p->capture_ns > p->time_ns + std::int64_t(period_us * 1000.0));
      // Firing times within the packet: 55.296 us per sequence, 2.304 us per laser.
      const int seq_of_block = mode == ReturnMode::dual ? 10 : 5 * 2;  // block 10 or 5
      const int block = mode == ReturnMode::dual ? 10 : 5;
      const auto slot = static_cast<std::size_t>(block * 32 + 16 + 3);
      const std::int64_t seq = seq_of_block + (mode == ReturnMode::dual ? 1 : 1);
      CHECK(p->truth[slot].time_ns == p->time_ns + seq * 55'296 + 3 * 2'304);
    }
  }
}

TEST_CASE("labels align with distances and with the truth", "[sim]") {
  for (const auto kind : {SceneKind::urban, SceneKind::hills, SceneKind::jam}) {
    const Simulator sim(config_for(kind));
    const Terrain& terrain = sim.scene().terrain();
    auto p = std::make_unique<SimulatedPacket>();
    int counts[4] = {0, 0, 0, 0};
    for (std::uint64_t k = 0; k < sim.packet_count(); k += 3) {
      sim.simulate_packet(k, *p);
      for (int b = 0; b < 12; ++b) {
        for (int c = 0; c < 32; ++c) {
          const auto slot = static_cast<std::size_t>(b * 32 + c);
          const std::uint8_t label = p->labels[slot];
          REQUIRE(label <= 3);
          ++counts[label];
          REQUIRE((label == 0) == (distance_at(*p, b, c) == 0));
          if (label == 0) continue;
          const SlotTruth& t = p->truth[slot];
          CHECK(std::fabs(distance_at(*p, b, c) * 0.002 - t.range_m) <= 0.001 + 1e-9);
          const double above = t.world_point.z - terrain.height(t.world_point.x, t.world_point.y);
          if (label == 1) {
            // On the terrain surface, or on a curb face (vertical, at the road edge).
            const bool on_curb =
                terrain.curb_height_m > 0.0 &&
                std::fabs(std::fabs(t.world_point.y) - terrain.road_half_width_m) < 0.01;
            REQUIRE((std::fabs(above) < 0.02 || on_curb));
          } else if (label == 2) {
            REQUIRE(above >= 0.15);
          } else {
            REQUIRE(above < 0.15);
          }
        }
      }
    }
    CHECK(counts[1] > 1000);
    CHECK(counts[2] > 300);
    const double dropout = double(counts[0]) / (counts[0] + counts[1] + counts[2] + counts[3]);
    CHECK(dropout > 0.0);
  }
}

TEST_CASE("ground points lie at the mounting height below a level sensor", "[sim]") {
  SimConfig c = config_for(SceneKind::fences);
  c.sensor_height_m = 1.5;
  c.range_noise_m = 0.0;
  const Simulator sim(c);
  auto p = std::make_unique<SimulatedPacket>();
  sim.simulate_packet(3, *p);
  int near_ground = 0;
  for (std::size_t s = 0; s < 384; ++s) {
    const SlotTruth& t = p->truth[s];
    if (p->labels[s] != 1 || std::hypot(t.sensor_point.x, t.sensor_point.y) > 6.0) continue;
    // Fences terrain is within +-0.15 m of zero.
    CHECK(t.sensor_point.z == Approx(-1.5).margin(0.2));
    ++near_ground;
  }
  CHECK(near_ground > 10);
}

TEST_CASE("mount pitch tilts the ground in the sensor frame", "[sim]") {
  SimConfig c = config_for(SceneKind::flat);  // level terrain everywhere
  c.range_noise_m = 0.0;
  c.mount_pitch_deg = -5.0;  // nose up (right-handed about y): ground ahead appears lower
  c.sensor_height_m = 1.8;
  const Simulator sim(c);
  const double sp = std::sin(5.0 * 3.14159265358979 / 180.0);
  const double cp = std::cos(5.0 * 3.14159265358979 / 180.0);
  auto p = std::make_unique<SimulatedPacket>();
  int ahead = 0, behind = 0;
  for (std::uint64_t k = 0; k < sim.packet_count(); k += 2) {
    sim.simulate_packet(k, *p);
    for (std::size_t s = 0; s < 384; ++s) {
      const Vec3& q = p->truth[s].sensor_point;
      if (p->labels[s] != 1 || std::fabs(q.x) > 25.0) continue;
      // World z of a sensor-frame point under a nose-up pitch: sin(p) x + cos(p) z = -height.
      REQUIRE(sp * q.x + cp * q.z == Approx(-1.8).margin(0.01));
      (q.x > 0 ? ahead : behind)++;
    }
  }
  CHECK(ahead > 100);
  CHECK(behind > 100);
}

TEST_CASE("dual return: pairs share azimuth, second echoes behind canopies", "[sim]") {
  const Simulator sim(config_for(SceneKind::hills, ReturnMode::dual, 1));
  auto p = std::make_unique<SimulatedPacket>();
  int differing = 0;
  for (std::uint64_t k = 0; k < sim.packet_count(); ++k) {
    sim.simulate_packet(k, *p);
    REQUIRE(p->bytes[1204] == kModeDual);
    for (int b = 0; b < 12; b += 2) {
      const auto at = static_cast<std::size_t>(100 * b + 2);
      REQUIRE(std::memcmp(p->bytes.data() + at, p->bytes.data() + at + 100, 2) == 0);
      for (int c = 0; c < 32; ++c) {
        const unsigned last = distance_at(*p, b, c);
        const unsigned other = distance_at(*p, b + 1, c);
        if (last != other) {
          ++differing;
          // The even block holds the last echo: farther than the other one.
          REQUIRE(other != 0);
          REQUIRE(last > other);
        }
      }
    }
  }
  CHECK(differing > 20);
}

TEST_CASE("last-return mode reports the farther echo", "[sim]") {
  SimConfig c = config_for(SceneKind::hills, ReturnMode::last);
  const Simulator last(c);
  c.mode = ReturnMode::dual;
  const Simulator dual(c);
  auto a = std::make_unique<SimulatedPacket>();
  auto b = std::make_unique<SimulatedPacket>();
  last.simulate_packet(10, *a);
  CHECK(a->bytes[1204] == kModeLast);
  // Same rays: the dual packet 20 starts where the single packet 10 starts.
  dual.simulate_packet(20, *b);
  for (int c2 = 0; c2 < 32; ++c2) CHECK(distance_at(*a, 0, c2) == distance_at(*b, 0, c2));
}

TEST_CASE("simulation is deterministic per seed and differs across seeds", "[sim]") {
  SimConfig c = config_for(SceneKind::urban);
  const Simulator a(c);
  const Simulator b(c);
  c.seed = 12;
  const Simulator other(c);
  auto pa = std::make_unique<SimulatedPacket>();
  auto pb = std::make_unique<SimulatedPacket>();
  a.simulate_packet(17, *pa);
  b.simulate_packet(17, *pb);
  CHECK(pa->bytes == pb->bytes);
  CHECK(pa->labels == pb->labels);
  other.simulate_packet(17, *pb);
  CHECK(pa->bytes != pb->bytes);
}

TEST_CASE("capture covers the requested number of rotations", "[sim]") {
  for (const double rpm : {300.0, 600.0, 1200.0}) {
    SimConfig c = config_for(SceneKind::flat, ReturnMode::strongest, 3);
    c.rpm = rpm;
    const Simulator sim(c);
    auto p = std::make_unique<SimulatedPacket>();
    int crossings = 0;
    int previous = -1;
    for (std::uint64_t k = 0; k < sim.packet_count(); ++k) {
      sim.simulate_packet(k, *p);
      for (std::size_t b = 0; b < 12; ++b) {
        const int az = p->bytes[100 * b + 2] | (p->bytes[100 * b + 3] << 8);
        REQUIRE(az < 36000);
        if (previous >= 0 && az < previous) ++crossings;
        previous = az;
      }
    }
    CHECK(crossings == c.frames + 1);  // the first crossing opens frame 1
  }
}

TEST_CASE("position packets follow every 14th data packet with locked PPS", "[sim]") {
  const Simulator sim(config_for(SceneKind::flat));
  SimulatedPositionPacket pos;
  CHECK_FALSE(sim.position_after(0, pos));
  CHECK_FALSE(sim.position_after(12, pos));
  REQUIRE(sim.position_after(13, pos));
  CHECK(pos.bytes[202] == 2);
  const std::string nmea(reinterpret_cast<const char*>(pos.bytes.data() + 206));
  CHECK(nmea.rfind("$GPRMC,220001.00,A,", 0) == 0);
  CHECK(nmea.find(",141123,") != std::string::npos);
  // Stamp and capture clock agree.
  const std::int64_t stamp_us = le32(pos.bytes.data() + 198);
  const std::int64_t capture_us_past_hour = (pos.capture_ns / 1000) % 3'600'000'000;
  CHECK(std::llabs(capture_us_past_hour - stamp_us) < 100);
  REQUIRE(sim.position_after(27, pos));
}

TEST_CASE("invalid configurations are rejected", "[sim]") {
  SimConfig c;
  c.rpm = 1500;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
  c = SimConfig{};
  c.frames = 0;
  CHECK_THROWS_AS(Simulator(c), std::invalid_argument);
  c = SimConfig{};
  c.dropout_probability = 2;
  CHECK_THROWS_AS(c.validate(), std::invalid_argument);
}
