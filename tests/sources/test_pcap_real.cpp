// Real captures: packet counts from the source against a deliberately simple, independent
// reading of the classic pcap records in the test (Ethernet, optional VLAN, IPv4, UDP).
#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <vector>

#include "test_data.hpp"
#include "vlpground/driver/packet_source.hpp"

using namespace vlpground;

namespace {

struct IndependentCount {
  std::uint64_t records = 0;
  std::uint64_t data = 0;
  std::uint64_t position = 0;
  std::uint64_t truncated_records = 0;
};

std::uint32_t le32(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at] | (b[at + 1] << 8) | (b[at + 2] << 16)) |
         (static_cast<std::uint32_t>(b[at + 3]) << 24);
}

std::size_t be16(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::size_t>((b[at] << 8) | b[at + 1]);
}

IndependentCount count_by_hand(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  const std::vector<unsigned char> b((std::istreambuf_iterator<char>(file)),
                                     std::istreambuf_iterator<char>());
  REQUIRE(b.size() >= 24);
  REQUIRE(le32(b, 0) == 0xa1b2c3d4u);  // little-endian, microseconds
  REQUIRE(le32(b, 20) == 1);           // Ethernet
  IndependentCount count;
  std::size_t at = 24;
  while (at < b.size()) {
    ++count.records;
    if (at + 16 > b.size()) {
      ++count.truncated_records;
      break;
    }
    const std::size_t caplen = le32(b, at + 8);
    const std::size_t len = le32(b, at + 12);
    const std::size_t frame = at + 16;
    at = frame + caplen;
    if (at > b.size() || caplen < len) {
      ++count.truncated_records;
      continue;
    }
    std::size_t type_at = frame + 12;
    while (be16(b, type_at) == 0x8100) type_at += 4;
    if (be16(b, type_at) != 0x0800) continue;
    const std::size_t ip = type_at + 2;
    const std::size_t udp = ip + (b[ip] & 0x0Fu) * 4u;
    if (b[ip + 9] != 17 || (be16(b, ip + 6) & 0x3FFF) != 0) continue;
    const std::size_t port = be16(b, udp + 2);
    const std::size_t payload = be16(b, udp + 4) - 8;
    if (port == 2368 && payload == 1206) ++count.data;
    if (port == 8308 && payload == 512) ++count.position;
  }
  return count;
}

void check_file(const std::string& name, bool expect_truncated_last) {
  const auto path = test::shared_file("real", name);
  VLPGROUND_REQUIRE_SHARED(path);
  INFO(name);
  const IndependentCount expected = count_by_hand(*path);
  PcapSourceConfig config;
  config.path = path->string();
  auto source = open_pcap_source(config);
  PacketView view;
  std::uint64_t data = 0;
  std::uint64_t position = 0;
  std::int64_t previous_ns = 0;
  SourceStatus status;
  while ((status = source->next(view, 0)) == SourceStatus::packet) {
    (view.kind == PacketKind::data ? data : position)++;
    CHECK(view.bytes.size() == (view.kind == PacketKind::data ? 1206u : 512u));
    if (view.kind == PacketKind::data) {
      CHECK(view.receive_ns >= previous_ns);  // data packets of these captures are in order
      previous_ns = view.receive_ns;
    }
  }
  CHECK(status == SourceStatus::end_of_file);
  const SourceCounters& c = source->counters();
  CHECK(data == expected.data);
  CHECK(position == expected.position);
  CHECK(c.data_packets == expected.data);
  CHECK(c.position_packets == expected.position);
  CHECK(c.records == expected.records);
  CHECK(c.truncated == expected.truncated_records);
  CHECK((expected.truncated_records > 0) == expect_truncated_last);
  CHECK(c.records == c.data_packets + c.position_packets + c.skipped());
  CHECK(expected.data > 0);
  CHECK(source->progress() == 1.0);
}

}  // namespace

TEST_CASE("pcap real: vlp16_short.pcap (stray ARP, truncated last record)") {
  check_file("vlp16_short.pcap", true);
  const auto path = test::shared_file("real", "vlp16_short.pcap");
  VLPGROUND_REQUIRE_SHARED(path);
  PcapSourceConfig config;
  config.path = path->string();
  auto source = open_pcap_source(config);
  PacketView view;
  while (source->next(view, 0) == SourceStatus::packet) {
  }
  CHECK(source->counters().skipped_other >= 1);  // the ARP frame
}

TEST_CASE("pcap real: vlp16_outdoor_600rpm.pcap (truncated last record)") {
  check_file("vlp16_outdoor_600rpm.pcap", true);
}

TEST_CASE("pcap real: vlp16_dual_close_range.pcap") {
  check_file("vlp16_dual_close_range.pcap", false);
}

TEST_CASE("pcap real: vlp16_indoor_gps.pcap") { check_file("vlp16_indoor_gps.pcap", false); }
