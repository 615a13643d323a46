// Replay of captures written byte by byte in the test: every link type, VLAN, IPv6, IPv4
// options, fragments, wrong sizes, other traffic, address filter, truncation, pcapng, errors.
#include <catch2/catch.hpp>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "capture_builder.hpp"
#include "test_data.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/types.hpp"

using namespace vlpground;
using namespace vlpground::test;

namespace {

constexpr std::int64_t kT0 = 1'700'000'000'123'456'789;  // ns since epoch

struct Received {
  PacketKind kind;
  Bytes bytes;
  std::int64_t receive_ns;
};

std::vector<Received> drain(PacketSource& source) {
  std::vector<Received> got;
  PacketView view;
  for (;;) {
    const SourceStatus status = source.next(view, 100);
    if (status != SourceStatus::packet) {
      REQUIRE(status == SourceStatus::end_of_file);
      return got;
    }
    CHECK(view.steady_receive_ns != 0);
    got.push_back({view.kind, Bytes(view.bytes.begin(), view.bytes.end()), view.receive_ns});
  }
}

std::unique_ptr<PacketSource> open(const std::filesystem::path& path, std::string sensor = "") {
  PcapSourceConfig config;
  config.path = path.string();
  config.sensor_address = std::move(sensor);
  return open_pcap_source(config);
}

Bytes data_payload(std::uint8_t seed) { return pattern_payload(1206, seed); }
Bytes position_payload(std::uint8_t seed) { return pattern_payload(512, seed); }

void check_balanced(const SourceCounters& c) {
  CHECK(c.records == c.data_packets + c.position_packets + c.skipped());
}

}  // namespace

TEST_CASE("pcap: Ethernet capture with every kind of traffic is classified and counted") {
  const auto dir = temp_dir("sources_ethernet");
  Ipv4Spec options;
  options.option_bytes = 12;
  Ipv4Spec first_fragment;
  first_fragment.more_fragments = true;
  Ipv4Spec later_fragment;
  later_fragment.fragment_offset = 185;
  Ipv4Spec tcp;
  tcp.protocol = 6;
  Ipv6Spec v6_ext;
  v6_ext.extensions = {0, 43, 60, 51};
  Ipv6Spec v6_fragment;
  v6_fragment.extensions = {0, 44};
  Record snapped{kT0 + 900, ethernet(udp_ipv4(data_payload(9), 2368))};
  snapped.original_length = static_cast<std::uint32_t>(snapped.bytes.size());
  snapped.bytes.resize(200);

  const std::vector<Record> records = {
      {kT0 + 0, ethernet(udp_ipv4(data_payload(1), 2368))},
      {kT0 + 100, ethernet(udp_ipv4(position_payload(2), 8308))},
      {kT0 + 200, ethernet(udp_ipv4(data_payload(3), 2368), {0x8100})},
      {kT0 + 300, ethernet(udp_ipv4(data_payload(4), 2368), {0x88A8, 0x8100})},
      {kT0 + 400, ethernet(udp_ipv4(data_payload(5), 2368, options))},
      {kT0 + 500, ethernet(udp_ipv6(data_payload(6), 2368, v6_ext))},
      {kT0 + 510, ethernet(udp_ipv6(position_payload(7), 8308), {0x9100, 0x8100})},
      {kT0 + 600, ethernet(udp_ipv4(data_payload(0), 2368, first_fragment))},
      {kT0 + 610, ethernet(udp_ipv4(pattern_payload(100, 0), 2368, later_fragment))},
      {kT0 + 620, ethernet(udp_ipv6(data_payload(0), 2368, v6_fragment))},
      {kT0 + 700, ethernet(udp_ipv4(pattern_payload(1200, 0), 2368))},  // wrong size
      {kT0 + 710, ethernet(udp_ipv4(data_payload(0), 8308))},           // data size on pos port
      {kT0 + 720, ethernet(udp_ipv4(data_payload(0), 2369))},           // other port
      {kT0 + 730, ethernet_arp()},
      {kT0 + 740, ethernet(udp_ipv4(data_payload(0), 2368, tcp))},
      snapped,
      {kT0 + 1000, ethernet(udp_ipv4(data_payload(8), 2368))},
      {kT0 + 1100, ethernet(udp_ipv4(data_payload(0), 2368))},  // cut short below
  };
  const auto path = dir / "mixed.pcap";
  write_pcap(path, 1, records, true, 300);

  auto source = open(path);
  CHECK_FALSE(source->is_live());
  CHECK(source->describe() == "pcap " + path.string());
  const auto got = drain(*source);

  const std::vector<std::pair<PacketKind, Bytes>> expected = {
      {PacketKind::data, data_payload(1)},         {PacketKind::position, position_payload(2)},
      {PacketKind::data, data_payload(3)},         {PacketKind::data, data_payload(4)},
      {PacketKind::data, data_payload(5)},         {PacketKind::data, data_payload(6)},
      {PacketKind::position, position_payload(7)}, {PacketKind::data, data_payload(8)},
  };
  const std::vector<std::int64_t> stamps = {0, 100, 200, 300, 400, 500, 510, 1000};
  REQUIRE(got.size() == expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    INFO("packet " << i);
    CHECK(got[i].kind == expected[i].first);
    CHECK(got[i].bytes == expected[i].second);
    CHECK(got[i].receive_ns == kT0 + stamps[i]);
  }
  const SourceCounters& c = source->counters();
  CHECK(c.records == records.size());
  CHECK(c.data_packets == 6);
  CHECK(c.position_packets == 2);
  CHECK(c.skipped_fragment == 3);
  CHECK(c.skipped_wrong_size == 2);
  CHECK(c.skipped_other == 3);  // other port, ARP, TCP
  CHECK(c.truncated == 2);      // snapped record, truncated last record
  CHECK(c.skipped_address == 0);
  check_balanced(c);
  CHECK(source->progress() == 1.0);
  PacketView view;
  CHECK(source->next(view, 0) == SourceStatus::end_of_file);
}

struct LinkCase {
  const char* name;
  std::uint32_t link_type;
  Bytes (*wrap)(const Bytes&);
};

TEST_CASE("pcap: every supported link type carries IPv4 and IPv6 packets") {
  const LinkCase link = GENERATE(
      LinkCase{"ethernet", 1, [](const Bytes& ip) { return ethernet(ip); }},
      LinkCase{"sll", 113, [](const Bytes& ip) { return linux_sll(ip); }},
      LinkCase{"sll2", 276, [](const Bytes& ip) { return linux_sll2(ip); }},
      LinkCase{"raw12", 12, [](const Bytes& ip) { return ip; }},
      LinkCase{"raw14", 14, [](const Bytes& ip) { return ip; }},
      LinkCase{"raw101", 101, [](const Bytes& ip) { return ip; }},
      LinkCase{"null_host_order", 0,
               [](const Bytes& ip) { return loopback(ip, (ip[0] >> 4) == 6 ? 30u : 2u, false); }},
      LinkCase{"null_swapped_order", 0,
               [](const Bytes& ip) { return loopback(ip, (ip[0] >> 4) == 6 ? 24u : 2u, true); }},
      LinkCase{"loop", 108,
               [](const Bytes& ip) { return loopback(ip, (ip[0] >> 4) == 6 ? 28u : 2u, true); }});
  INFO(link.name);
  const bool pcapng = GENERATE(false, true);
  INFO((pcapng ? "pcapng" : "pcap"));
  const auto dir = temp_dir(std::string("sources_link_") + link.name);
  const std::vector<Record> records = {
      {kT0, link.wrap(udp_ipv4(data_payload(11), 2368))},
      {kT0 + 1, link.wrap(udp_ipv6(position_payload(12), 8308))},
      {kT0 + 2, link.wrap(udp_ipv4(pattern_payload(40, 0), 53))},
      {kT0 + 3, link.wrap(udp_ipv6(data_payload(13), 2368))},
  };
  const auto path = dir / (pcapng ? "cap.pcapng" : "cap.pcap");
  if (pcapng) {
    write_pcapng(path, static_cast<std::uint16_t>(link.link_type), records);
  } else {
    write_pcap(path, link.link_type, records);
  }
  auto source = open(path);
  const auto got = drain(*source);
  REQUIRE(got.size() == 3);
  CHECK(got[0].bytes == data_payload(11));
  CHECK(got[1].kind == PacketKind::position);
  CHECK(got[1].bytes == position_payload(12));
  CHECK(got[2].bytes == data_payload(13));
  CHECK(got[2].receive_ns == kT0 + 3);  // nanosecond stamps survive both formats
  CHECK(source->counters().skipped_other == 1);
  check_balanced(source->counters());
}

TEST_CASE("pcap: microsecond captures give stamps in nanoseconds") {
  const auto path = temp_dir("sources_usec") / "usec.pcap";
  write_pcap(path, 1, {{kT0, ethernet(udp_ipv4(data_payload(1), 2368))}}, false);
  const auto got = drain(*open(path));
  REQUIRE(got.size() == 1);
  CHECK(got[0].receive_ns == kT0 / 1000 * 1000);
}

TEST_CASE("pcap: sensor address filter keeps only the chosen sender") {
  const auto path = temp_dir("sources_filter") / "two_sensors.pcap";
  Ipv4Spec other_sensor;
  other_sensor.source = {192, 168, 1, 202};
  Ipv6Spec v6_other;
  v6_other.source[15] = 2;
  write_pcap(path, 1,
             {
                 {kT0, ethernet(udp_ipv4(data_payload(1), 2368))},
                 {kT0 + 1, ethernet(udp_ipv4(data_payload(2), 2368, other_sensor))},
                 {kT0 + 2, ethernet(udp_ipv6(data_payload(3), 2368))},
                 {kT0 + 3, ethernet(udp_ipv6(data_payload(4), 2368, v6_other))},
                 {kT0 + 4, ethernet(udp_ipv4(position_payload(5), 8308, other_sensor))},
             });

  SECTION("IPv4 sensor") {
    auto source = open(path, "192.168.1.201");
    const auto got = drain(*source);
    REQUIRE(got.size() == 1);
    CHECK(got[0].bytes == data_payload(1));
    CHECK(source->counters().skipped_address == 4);
  }
  SECTION("IPv6 sensor") {
    auto source = open(path, "2001:db8::2");
    const auto got = drain(*source);
    REQUIRE(got.size() == 1);
    CHECK(got[0].bytes == data_payload(4));
    CHECK(source->counters().skipped_address == 4);
  }
  SECTION("no filter") { CHECK(drain(*open(path)).size() == 5); }
}

TEST_CASE("pcap: configurable ports select the packets") {
  const auto path = temp_dir("sources_ports") / "ports.pcap";
  write_pcap(path, 1,
             {
                 {kT0, ethernet(udp_ipv4(data_payload(1), 2368))},
                 {kT0 + 1, ethernet(udp_ipv4(data_payload(2), 2370))},
                 {kT0 + 2, ethernet(udp_ipv4(position_payload(3), 8310))},
             });
  PcapSourceConfig config;
  config.path = path.string();
  config.data_port = 2370;
  config.position_port = 8310;
  auto source = open_pcap_source(config);
  const auto got = drain(*source);
  REQUIRE(got.size() == 2);
  CHECK(got[0].bytes == data_payload(2));
  CHECK(got[1].kind == PacketKind::position);
  CHECK(source->counters().skipped_other == 1);
}

TEST_CASE("pcap: invalid configuration is rejected by validate()") {
  PcapSourceConfig config;
  config.path = "x.pcap";
  CHECK_NOTHROW(config.validate());
  SECTION("bad sensor address") {
    config.sensor_address = "192.168.1.300";
    CHECK_THROWS_AS(config.validate(), std::invalid_argument);
    CHECK_THROWS_AS(open_pcap_source(config), std::invalid_argument);
  }
  SECTION("negative rate") {
    config.rate = -1.0;
    CHECK_THROWS_AS(config.validate(), std::invalid_argument);
  }
  SECTION("empty path") {
    config.path.clear();
    CHECK_THROWS_AS(config.validate(), std::invalid_argument);
  }
  SECTION("IPv6 address accepted") {
    config.sensor_address = "fe80::1";
    CHECK_NOTHROW(config.validate());
  }
}

TEST_CASE("pcap: missing, garbage and empty files are one-line runtime errors") {
  const auto dir = temp_dir("sources_errors");
  PcapSourceConfig config;
  auto check_error = [&](const std::filesystem::path& path) {
    config.path = path.string();
    try {
      open_pcap_source(config);
      FAIL("no exception for " << path);
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      INFO(message);
      CHECK(message.find(path.string()) != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
  };
  check_error(dir / "does_not_exist.pcap");
  {
    std::ofstream garbage(dir / "garbage.pcap");
    garbage << "this is not a capture file, just some text that is long enough\n";
  }
  check_error(dir / "garbage.pcap");
  { std::ofstream empty(dir / "empty.pcap"); }
  check_error(dir / "empty.pcap");
  write_pcap(dir / "unsupported.pcap", 105, {});  // 802.11
  check_error(dir / "unsupported.pcap");
}

TEST_CASE("pcap: looping replays the capture with increasing stamps until stopped") {
  const auto path = temp_dir("sources_loop") / "loop.pcap";
  write_pcap(path, 1,
             {
                 {kT0, ethernet(udp_ipv4(data_payload(1), 2368))},
                 {kT0 + 1000, ethernet_arp()},
                 {kT0 + 2000, ethernet(udp_ipv4(data_payload(2), 2368))},
             });
  PcapSourceConfig config;
  config.path = path.string();
  config.loop = true;
  auto source = open_pcap_source(config);
  PacketView view;
  std::vector<std::int64_t> stamps;
  for (int i = 0; i < 7; ++i) {
    REQUIRE(source->next(view, 0) == SourceStatus::packet);
    CHECK(view.bytes.size() == 1206);
    CHECK(view.bytes[0] == data_payload(i % 2 == 0 ? 1 : 2)[0]);
    stamps.push_back(view.receive_ns);
  }
  // Span 2000 ns plus the mean spacing (1000 ns, raised to the 1 us minimum) per pass.
  CHECK(stamps[2] == kT0 + 3000);
  CHECK(stamps[4] == kT0 + 6000);
  for (std::size_t i = 1; i < stamps.size(); ++i) CHECK(stamps[i] > stamps[i - 1]);
  CHECK(source->counters().data_packets == 7);
  source->request_stop();
  CHECK(source->next(view, 0) == SourceStatus::stopped);
}

TEST_CASE("pcap: looping joins the end of a capture to its start as one recording") {
  // The demo capture: 283 data packets, 0.73 + 3 + 0.02 rotations at 600 rpm.
  PcapSourceConfig config;
  config.path = project_pcap("urban_demo.pcap").string();
  config.loop = true;
  auto source = open_pcap_source(config);
  const auto stamp_us = [](const PacketView& v) {
    return static_cast<std::int64_t>(v.bytes[1200]) | std::int64_t{v.bytes[1201]} << 8 |
           std::int64_t{v.bytes[1202]} << 16 | std::int64_t{v.bytes[1203]} << 24;
  };
  const auto degrees = [](const PacketView& v, std::size_t block) {
    return (v.bytes[block * 100 + 2] | v.bytes[block * 100 + 3] << 8) / 100.0;
  };
  PacketView view;
  std::int64_t last_time_ns = 0, last_receive_ns = 0, last_offset_ns = 0;
  double last_final_deg = 0;
  int data = 0, joins = 0;
  while (data < 283 + 100) {  // into the second pass
    REQUIRE(source->next(view, 0) == SourceStatus::packet);
    if (view.kind != PacketKind::data) continue;
    ++data;
    // The sensor's clock as the decoder sees it: stamp plus the pass's offset.
    const std::int64_t time_ns = stamp_us(view) * 1000 + view.stamp_offset_ns;
    if (data > 1) {
      // Every step, the seam's too, is one packet period (1327 or 1328 us stamps).
      const std::int64_t step = time_ns - last_time_ns;
      CHECK(step >= 1'327'000);
      CHECK(step <= 1'328'000);
      CHECK(view.receive_ns > last_receive_ns);
      if (view.stamp_offset_ns != last_offset_ns) {  // the seam
        ++joins;
        CHECK(step == kSinglePacketPeriodNs);
        // The rotation continues: the first firing is at most one packet's sweep after the
        // previous pass's last block.
        double advance = degrees(view, 0) - last_final_deg;
        if (advance < 0) advance += 360;
        CHECK(advance > 0);
        CHECK(advance <= 5.0);
      }
    }
    last_offset_ns = view.stamp_offset_ns;
    last_time_ns = time_ns;
    last_receive_ns = view.receive_ns;
    last_final_deg = degrees(view, 11);
  }
  CHECK(joins == 1);
  const SourceCounters& c = source->counters();
  CHECK(c.loop_wraps == 1);
  // The second pass skipped the packets before the continuation (the 0.73 partial turn and
  // then some), counted, and not as data.
  CHECK(c.skipped_loop > 50);
  CHECK(c.skipped_loop < 80);
  CHECK(c.data_packets == 283 + 100);
  CHECK(c.records == c.data_packets + c.position_packets + c.skipped());
}

TEST_CASE("pcap: looping a capture without packets ends instead of spinning") {
  const auto path = temp_dir("sources_loop_empty") / "arp_only.pcap";
  write_pcap(path, 1, {{kT0, ethernet_arp()}});
  PcapSourceConfig config;
  config.path = path.string();
  config.loop = true;
  auto source = open_pcap_source(config);
  PacketView view;
  CHECK(source->next(view, 0) == SourceStatus::end_of_file);
}

TEST_CASE("pcap: paced replay holds a packet until due, and stop ends the wait") {
  const auto path = temp_dir("sources_paced") / "paced.pcap";
  const std::int64_t hour_ns = 3600LL * 1'000'000'000;
  write_pcap(path, 1,
             {
                 {kT0, ethernet(udp_ipv4(data_payload(1), 2368))},
                 {kT0 + hour_ns, ethernet(udp_ipv4(data_payload(2), 2368))},
             });
  PcapSourceConfig config;
  config.path = path.string();
  config.rate = 1.0;
  auto source = open_pcap_source(config);
  PacketView view;
  REQUIRE(source->next(view, 0) == SourceStatus::packet);  // the first one is due at once
  CHECK(source->next(view, 0) == SourceStatus::timeout);   // the second one is an hour away
  CHECK(source->next(view, 1) == SourceStatus::timeout);
  CHECK(source->counters().data_packets == 2);  // read once, held, not re-counted
  source->request_stop();
  CHECK(source->next(view, -1) == SourceStatus::stopped);
}

TEST_CASE("pcap: a very high rate delivers every packet") {
  const auto path = temp_dir("sources_fast") / "fast.pcap";
  std::vector<Record> records;
  for (int i = 0; i < 5; ++i) {
    records.push_back({kT0 + i * 1'327'000LL,
                       ethernet(udp_ipv4(data_payload(static_cast<std::uint8_t>(i)), 2368))});
  }
  write_pcap(path, 1, records);
  PcapSourceConfig config;
  config.path = path.string();
  config.rate = 1e9;
  auto source = open_pcap_source(config);
  CHECK(drain(*source).size() == 5);
}

TEST_CASE("pcap: progress grows from 0 to 1") {
  const auto path = temp_dir("sources_progress") / "progress.pcap";
  std::vector<Record> records;
  for (int i = 0; i < 20; ++i) {
    records.push_back(
        {kT0 + i, ethernet(udp_ipv4(data_payload(static_cast<std::uint8_t>(i)), 2368))});
  }
  write_pcap(path, 1, records);
  auto source = open(path);
  const double at_start = source->progress();
  CHECK(at_start >= 0.0);
  CHECK(at_start < 0.1);
  PacketView view;
  for (int i = 0; i < 10; ++i) REQUIRE(source->next(view, 0) == SourceStatus::packet);
  const double halfway = source->progress();
  CHECK(halfway > 0.3);
  CHECK(halfway < 0.7);
  drain(*source);
  CHECK(source->progress() == 1.0);
}
