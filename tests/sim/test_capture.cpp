// write_capture: pcap framing, checksums, labels and heights alignment and the json description.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <vector>

#include "test_data.hpp"
#include "vlpground/sim/capture_writer.hpp"

using namespace vlpground;
using namespace vlpground::sim;

namespace {

std::vector<std::uint8_t> slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
std::uint32_t le32(const std::uint8_t* p) {
  return p[0] | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}
unsigned be16(const std::uint8_t* p) { return (unsigned{p[0]} << 8) | p[1]; }
std::int16_t le16s(const std::uint8_t* p) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (unsigned{p[1]} << 8)));
}
// RFC 1071 sum, folded: 0xFFFF over a block including its correct checksum.
unsigned ones_sum(const std::uint8_t* p, std::size_t n, unsigned sum = 0) {
  for (std::size_t i = 0; i + 1 < n; i += 2) sum += be16(p + i);
  if (n % 2) sum += unsigned{p[n - 1]} << 8;
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return sum;
}

}  // namespace

TEST_CASE("capture files: pcap records, checksums, labels and json agree", "[sim][capture]") {
  SimConfig c;
  c.scene = SceneKind::slope;
  c.seed = 4;
  c.frames = 1;
  const Simulator sim(c);
  const auto stem = test::temp_dir("sim_capture") / "slope";
  const CaptureSummary summary = write_capture(sim, stem);
  CHECK(summary.data_packets == sim.packet_count());
  CHECK(summary.position_packets == sim.packet_count() / 14);

  const auto pcap = slurp(stem.string() + ".pcap");
  const auto labels = slurp(stem.string() + ".labels");
  REQUIRE(pcap.size() > 24);
  CHECK(le32(pcap.data()) == 0xA1B2C3D4u);
  CHECK(le32(pcap.data() + 20) == 1u);
  REQUIRE(labels.size() == summary.data_packets * 384);

  std::size_t off = 24, data = 0, position = 0;
  std::uint64_t previous_us = 0;
  auto packet = std::make_unique<SimulatedPacket>();
  while (off + 16 <= pcap.size()) {
    const std::uint8_t* rec = pcap.data() + off;
    const std::uint64_t us = std::uint64_t{le32(rec)} * 1'000'000 + le32(rec + 4);
    CHECK(us >= previous_us);
    previous_us = us;
    const std::uint32_t len = le32(rec + 8);
    const std::uint8_t* f = rec + 16;
    REQUIRE(off + 16 + len <= pcap.size());
    CHECK(ones_sum(f + 14, 20) == 0xFFFF);  // IPv4 header checksum
    const unsigned udp_len = be16(f + 38);
    unsigned pseudo = ones_sum(f + 26, 8) + 17 + udp_len;
    CHECK(ones_sum(f + 34, udp_len, pseudo) == 0xFFFF);  // UDP checksum with pseudo-header
    const unsigned port = be16(f + 36);
    if (port == kDataPort) {
      REQUIRE(len == 1248);
      sim.simulate_packet(data, *packet);
      CHECK(std::equal(packet->bytes.begin(), packet->bytes.end(), f + 42));
      // Labels of the k-th data packet sit at k * 384.
      CHECK(std::equal(packet->labels.begin(), packet->labels.end(),
                       labels.begin() + static_cast<long>(data * 384)));
      ++data;
    } else {
      REQUIRE(port == kPositionPort);
      REQUIRE(len == 554);
      CHECK(data % 14 == 0);
      ++position;
    }
    off += 16 + len;
  }
  CHECK(off == pcap.size());
  CHECK(data == summary.data_packets);
  CHECK(position == summary.position_packets);

  std::ifstream json_in(stem.string() + ".json");
  const auto j = nlohmann::json::parse(json_in);
  CHECK(j.at("scene") == "slope");
  CHECK(j.at("seed") == 4);
  CHECK(j.at("mode") == "strongest");
  CHECK(j.at("model") == "vlp16");
  CHECK(j.at("packets") == summary.data_packets);
  CHECK(j.at("sensor_height_m").get<double>() == sim.sensor_height_m());
  CHECK(j.at("mount_roll_pitch_deg").size() == 2);
  CHECK(j.at("objects") == sim.scene().obstacles().size());
}

TEST_CASE("heights: centimetres rounded down, so they agree with the labels' 0.15 m",
          "[sim][capture]") {
  CHECK(height_above_terrain_cm(0.15) == 15);
  CHECK(height_above_terrain_cm(0.1499) == 14);
  CHECK(height_above_terrain_cm(0.509) == 50);
  CHECK(height_above_terrain_cm(-0.004) == -1);
  CHECK(height_above_terrain_cm(1e6) == 32767);  // saturated
  CHECK(height_above_terrain_cm(-1e6) == -32768);
}

TEST_CASE("capture files: the heights file agrees with the labels", "[sim][capture]") {
  SimConfig c;
  c.scene = SceneKind::bank;  // bushes on a steep face: obstacles of every height
  c.seed = 2;
  c.frames = 1;
  const Simulator sim(c);
  const auto stem = test::temp_dir("sim_heights") / "bank";
  const CaptureSummary summary = write_capture(sim, stem);
  const auto labels = slurp(stem.string() + ".labels");
  const auto heights = slurp(stem.string() + ".heights");
  REQUIRE(labels.size() == summary.data_packets * 384);
  REQUIRE(heights.size() == 2 * labels.size());

  auto packet = std::make_unique<SimulatedPacket>();
  std::uint64_t counts[4] = {0, 0, 0, 0};
  int nonzero_ground = 0, low_obstacle_out = 0, obstacle_out = 0, off_truth = 0;
  for (std::uint64_t k = 0; k < summary.data_packets; ++k) {
    sim.simulate_packet(k, *packet);
    for (std::size_t slot = 0; slot < 384; ++slot) {
      const std::size_t i = k * 384 + slot;
      const std::int16_t cm = le16s(heights.data() + 2 * i);
      const auto label = static_cast<Label>(labels[i]);
      ++counts[labels[i]];
      if (label == Label::none || label == Label::ground) nonzero_ground += cm != 0;
      if (label == Label::obstacle) obstacle_out += cm < 15;
      if (label == Label::low_obstacle) low_obstacle_out += cm >= 15;
      if (label == Label::obstacle || label == Label::low_obstacle) {
        off_truth += std::fabs(cm * 0.01 - packet->truth[slot].above_terrain_m) > 0.01;
      }
      if (cm != packet->heights_cm[slot]) ++off_truth;
    }
  }
  CHECK(counts[2] > 100);
  CHECK(counts[3] > 0);
  CHECK(nonzero_ground == 0);
  CHECK(obstacle_out == 0);
  CHECK(low_obstacle_out == 0);
  CHECK(off_truth == 0);
}
