// CaptureReader over the shared captures: every data packet accounted for, frames and rpm as
// the capture's own stamps and azimuths say, foreign sensors refused with a reason.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_data.hpp"
#include "vlpground/driver/capture_reader.hpp"

using namespace vlpground;

namespace {

// What the raw bytes say, read without the decoder: packet-level azimuth wraps (= crossings of
// the 0 degree cut, each one inside or between packets) and the rotation rate.
struct RawFacts {
  std::uint64_t data_packets = 0;
  int wraps = 0;
  double rpm = 0.0;
};

RawFacts raw_facts(const std::string& path) {
  PcapSourceConfig config;
  config.path = path;
  auto source = open_pcap_source(config);
  RawFacts facts;
  PacketView view;
  int previous_az = -1;
  std::uint32_t first_stamp = 0, last_stamp = 0;
  double advance_deg = 0.0;
  while (source->next(view, 0) == SourceStatus::packet) {
    if (view.kind != PacketKind::data || view.bytes.size() != kDataPacketBytes) continue;
    std::uint32_t stamp = 0;
    std::memcpy(&stamp, view.bytes.data() + 1200, sizeof stamp);
    if (facts.data_packets++ == 0) first_stamp = stamp;
    last_stamp = stamp;
    for (std::size_t block = 0; block < 12; ++block) {
      std::uint16_t az = 0;
      std::memcpy(&az, view.bytes.data() + block * 100 + 2, sizeof az);
      if (previous_az >= 0) {
        if (az < previous_az) ++facts.wraps;
        advance_deg += ((az - previous_az + 36000) % 36000) / 100.0;
      }
      previous_az = az;
    }
  }
  if (last_stamp > first_stamp) {
    facts.rpm = advance_deg / 360.0 / ((last_stamp - first_stamp) * 1e-6) * 60.0;
  }
  return facts;
}

struct ReadResult {
  std::vector<FrameMeta> metas;
  std::vector<int> valid_columns;
  std::vector<std::string> warnings;
  CaptureCounters counters;
  int positions = 0;
};

ReadResult read_all(const std::string& path) {
  PcapSourceConfig config;
  config.path = path;
  CaptureReader reader(open_pcap_source(config));
  ReadResult r;
  reader.on_warning([&](std::error_code, const std::string& w) { r.warnings.push_back(w); });
  reader.on_position([&](const PositionPacket&) { ++r.positions; });
  Frame frame;
  ReadStatus status;
  while ((status = reader.next(frame, 0)) == ReadStatus::frame) {
    r.metas.push_back(frame.meta);
    int valid = 0;
    for (int c = 0; c < frame.columns(); ++c)
      valid += frame.column_valid[static_cast<std::size_t>(c)];
    r.valid_columns.push_back(valid);
  }
  CHECK(status == ReadStatus::end_of_input);
  CHECK(reader.next(frame, 0) == ReadStatus::end_of_input);
  r.counters = reader.counters();
  return r;
}

std::string json_value(const std::string& json_path, const std::string& key) {
  std::ifstream in(json_path);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  auto at = text.find("\"" + key + "\"");
  REQUIRE(at != std::string::npos);
  at = text.find(':', at) + 1;
  while (text[at] == ' ' || text[at] == '"') ++at;
  auto end = text.find_first_of(",\"\n}", at);
  return text.substr(at, end - at);
}

void check_accounting(const ReadResult& r, int columns_per_packet) {
  const auto& a = r.counters.assembler;
  CHECK(a.packets_used + a.packets_skipped() == r.counters.source.data_packets);
  long valid = 0;
  for (int v : r.valid_columns) valid += v;
  CHECK(valid == static_cast<long>(a.packets_used) * columns_per_packet);
  CHECK(r.positions == static_cast<int>(r.counters.source.position_packets));
}

}  // namespace

TEST_CASE("sim captures: frames, rpm and packet accounting", "[assembler][capture]") {
  const std::string stem = GENERATE("flat_strongest", "flat_dual", "flat_20hz", "urban_hires_last",
                                    "fences_dual", "jam_strongest");
  const auto pcap = test::shared_file("sim", stem + ".pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto json = test::shared_file("sim", stem + ".json");
  const double rpm = std::stod(json_value(json->string(), "rpm"));
  const std::string mode = json_value(json->string(), "mode");
  const RawFacts raw = raw_facts(pcap->string());
  INFO(stem << ": " << raw.data_packets << " packets, " << raw.wraps << " wraps");
  const ReadResult r = read_all(pcap->string());

  check_accounting(r, mode == "dual" ? 12 : 24);
  CHECK(r.counters.assembler.packets_used == raw.data_packets);
  CHECK(r.counters.assembler.packets_lost == 0);
  CHECK(r.counters.position_packets_parsed == r.counters.source.position_packets);
  // Leading partial, one complete frame between consecutive cuts, trailing partial.
  REQUIRE(r.metas.size() == static_cast<std::size_t>(raw.wraps + 1));
  CHECK_FALSE(r.metas.front().complete);
  CHECK_FALSE(r.metas.back().complete);
  for (std::size_t f = 1; f + 1 < r.metas.size(); ++f) {
    CHECK(r.metas[f].complete);
    CHECK(r.metas[f].rpm == Approx(rpm).epsilon(0.005));
    CHECK(r.metas[f].rpm == Approx(raw.rpm).epsilon(0.005));
    CHECK(std::string(to_string(r.metas[f].mode)) == mode);
    CHECK(r.metas[f].columns_lost == 0);
  }
  CHECK(r.warnings.empty());
}

TEST_CASE("real VLP-16 captures: frames, rpm and packet accounting", "[assembler][capture]") {
  struct Case {
    const char* name;
    double rpm;
    int columns_per_packet;
  };
  const Case c = GENERATE(Case{"vlp16_outdoor_600rpm.pcap", 600, 24},
                          Case{"vlp16_1200rpm_productbyte21.pcap", 1200, 24},
                          Case{"vlp16_county_fair_productbyte21.pcap", 600, 24},
                          Case{"vlp16_dual_close_range.pcap", 600, 12},
                          Case{"vlp16_indoor_gps.pcap", 600, 24});
  const auto pcap = test::shared_file("real", c.name);
  VLPGROUND_REQUIRE_SHARED(pcap);
  const RawFacts raw = raw_facts(pcap->string());
  INFO(c.name << ": " << raw.data_packets << " packets, " << raw.wraps << " wraps");
  const ReadResult r = read_all(pcap->string());
  check_accounting(r, c.columns_per_packet);
  // Packets the decoder refuses (a corrupt block) are skipped upstream, never lost silently.
  CHECK(r.counters.assembler.packets_used + r.counters.assembler.skipped_upstream ==
        raw.data_packets);
  CHECK(r.metas.size() == static_cast<std::size_t>(raw.wraps + 1));
  CHECK(raw.rpm == Approx(c.rpm).epsilon(0.03));
  for (const auto& m : r.metas) {
    if (m.complete) CHECK(m.rpm == Approx(raw.rpm).epsilon(0.01));
  }
}

TEST_CASE("a sparse 300 rpm capture with long gaps ends frames at the gaps",
          "[assembler][capture]") {
  const auto pcap = test::shared_file("real", "vlp16_short.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const RawFacts raw = raw_facts(pcap->string());
  const ReadResult r = read_all(pcap->string());
  check_accounting(r, 24);
  CHECK(r.counters.assembler.packets_used == raw.data_packets);
  // Two ~156 ms silences (~280 degrees at 300 rpm), edited in the middle of packets.
  CHECK(r.counters.assembler.large_gaps + r.counters.assembler.azimuth_jumps >= 2);
  CHECK(r.counters.assembler.columns_lost == 0);
  for (const auto& m : r.metas) {
    CHECK_FALSE(m.complete);
    if (m.packets_used >= 5) CHECK(m.rpm == Approx(300).epsilon(0.02));
  }
}

TEST_CASE("HDL-32E captures yield no frames and say why", "[assembler][capture]") {
  const std::string name = GENERATE("hdl32e_short.pcap", "hdl32e_monterey.pcap");
  const auto pcap = test::shared_file("real", name);
  VLPGROUND_REQUIRE_SHARED(pcap);
  const ReadResult r = read_all(pcap->string());
  // The decoder needs a few packets to judge the spacing; the frame those started is
  // discarded at the verdict.
  CHECK(r.metas.empty());
  CHECK(r.counters.assembler.packets_used == 0);
  CHECK(r.counters.assembler.discarded_packets >= 1);
  check_accounting(r, 24);
  REQUIRE_FALSE(r.warnings.empty());
  bool says_why = false;
  for (const auto& w : r.warnings) says_why = says_why || w.find("VLP-16") != std::string::npos;
  CHECK(says_why);
}
