// Position packets ($GPRMC, PPS) and the hour of the packet stamps.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>

#include "classic_pcap.hpp"
#include "test_data.hpp"
#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/position_packet.hpp"
#include "vlpground/sim/packet_encoder.hpp"

namespace {

using namespace vlpground;

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kHour = 3600 * kSecond;
// 2023-11-14 22:00:00 UTC.
constexpr std::int64_t kTopOfHourNs = 1'699'999'200 * kSecond;

// "$<body>*hh" with the NMEA checksum (XOR of the body) computed here.
std::string with_checksum(const std::string& body) {
  unsigned sum = 0;
  for (char c : body) sum ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", sum);
  return "$" + body + tail;
}

Gprmc parse(const std::string& s) { return parse_gprmc(s.data(), s.size()); }

std::array<std::uint8_t, kDataPacketBytes> data_packet(std::uint32_t stamp_us) {
  sim::DataPacketFields f;
  f.stamp_us_past_hour = stamp_us;
  std::array<std::uint8_t, kDataPacketBytes> bytes{};
  sim::encode_data_packet(f, bytes);
  return bytes;
}

}  // namespace

TEST_CASE("GPRMC: a good sentence", "[decoder][gprmc]") {
  const auto g = parse(
      with_checksum("GPRMC,214106.25,A,3707.8178,N,12139.2690,W,010.3,188.2,230715,013.8,E,D"));
  REQUIRE(g.parsed);
  CHECK(g.checksum_ok);
  CHECK(g.valid);
  CHECK(g.hour == 21);
  CHECK(g.minute == 41);
  CHECK(g.second == Approx(6.25));
  CHECK(g.day == 23);
  CHECK(g.month == 7);
  CHECK(g.year == 2015);
  CHECK(g.latitude_deg == Approx(37 + 7.8178 / 60));
  CHECK(g.longitude_deg == Approx(-(121 + 39.2690 / 60)));
  CHECK(g.speed_knots == Approx(10.3));
  CHECK(g.course_deg == Approx(188.2));
  // 2015-07-23 21:41:06.25 UTC = 1437687666.25 s since the epoch.
  CHECK(g.utc_ns() == 1'437'687'666'250'000'000);
}

TEST_CASE("GPRMC: bad checksum, void, empty and broken fields", "[decoder][gprmc]") {
  std::string good =
      with_checksum("GPRMC,220001,A,4807.0380,N,01131.0000,E,010.5,084.4,141123,003.1,W,A");
  REQUIRE(parse(good).parsed);
  std::string corrupted = good;
  corrupted[10] = '9';  // a digit of the time changed, checksum unchanged
  CHECK_FALSE(parse(corrupted).parsed);
  CHECK_FALSE(parse(corrupted).checksum_ok);

  const auto void_fix = parse(with_checksum("GPRMC,220001,V,,,,,,,141123,,,N"));
  CHECK(void_fix.parsed);  // time and date are usable
  CHECK(void_fix.checksum_ok);
  CHECK_FALSE(void_fix.valid);
  CHECK(void_fix.latitude_deg == 0.0);

  const auto empty = parse(with_checksum("GPRMC,,V,,,,,,,,,,N"));
  CHECK(empty.checksum_ok);
  CHECK_FALSE(empty.parsed);  // no time, no date

  CHECK_FALSE(
      parse(with_checksum("GPRMC,2200xx,A,4807.0380,N,01131.0000,E,0,0,141123,,,A")).parsed);
  CHECK_FALSE(parse(with_checksum("GPRMC,220001,A,4807.0380,Q,01131.0000,E,0,0,141123,,,A")).valid);
  CHECK_FALSE(
      parse(with_checksum("GPRMC,220001,A,4807.0380,N,01131.0000,E,0,0,141323,,,A")).parsed);
  CHECK_FALSE(
      parse(with_checksum("GPGGA,220001,4807.0380,N,01131.0000,E,1,08,0.9,545.4,M,,,,")).parsed);
  CHECK_FALSE(
      parse("$GPRMC,220001,A,4807.0380,N,01131.0000,E,010.5,084.4,141123,003.1,W,A").parsed);
  CHECK_FALSE(parse_gprmc(nullptr, 0).parsed);
  CHECK(parse(with_checksum("GNRMC,220001,A,4807.0380,N,01131.0000,E,010.5,084.4,141123,003.1,W,A"))
            .parsed);
}

TEST_CASE("GPRMC from the project's encoder round-trips", "[decoder][gprmc]") {
  const std::int64_t t = kTopOfHourNs + 61 * kSecond;
  const auto g = parse(sim::make_gprmc(t, true, -33.5, 151.25, 4.5, 270.0));
  REQUIRE(g.parsed);
  CHECK(g.valid);
  CHECK(g.utc_ns() / kSecond == t / kSecond);
  CHECK(g.latitude_deg == Approx(-33.5).margin(1e-5));
  CHECK(g.longitude_deg == Approx(151.25).margin(1e-5));
}

TEST_CASE("position packet: the real single-packet capture", "[decoder][gprmc]") {
  const auto path = test::shared_file("real", "vlp16_one_position_packet.pcap");
  VLPGROUND_REQUIRE_SHARED(path);
  const auto payloads = test::read_classic_pcap(*path);
  REQUIRE(payloads.position.size() == 1);
  PositionPacket p;
  REQUIRE(parse_position_packet(payloads.position[0].bytes, 7, p));
  CHECK(p.receive_ns == 7);
  CHECK(p.pps == PpsStatus::locked);
  CHECK(p.stamp_us_past_hour / 1'000'000 == 41 * 60 + 7);  // 21:41:06 fix, stamped 0.1 s on
  CHECK(std::string(p.sentence).rfind("$GPRMC,214106,A,", 0) == 0);
  REQUIRE(p.gprmc.parsed);
  CHECK(p.gprmc.valid);
  CHECK(p.gprmc.year == 2015);
  CHECK(p.gprmc.hour == 21);
  CHECK(p.gprmc.latitude_deg == Approx(37.13030).margin(1e-4));

  PositionPacket wrong;
  CHECK_FALSE(parse_position_packet(std::span(payloads.position[0].bytes).first(511), 0, wrong));
}

TEST_CASE("hour from the receive time: nearest hour, monotonic at the rollover",
          "[decoder][time]") {
  PacketDecoder decoder;
  DecodedPacket out;
  // Stamp 3599.9 s received just before the top of the hour, then 0.1 s just after.
  const std::int64_t hour = kTopOfHourNs;
  REQUIRE(decoder.decode(data_packet(3'599'900'000), hour - 99 * 1'000'000, out) ==
          DecodeStatus::ok);
  const std::int64_t before = out.time_ns;
  CHECK(before == hour - 100'000'000);
  REQUIRE(decoder.decode(data_packet(100'000), hour + 101 * 1'000'000, out) == DecodeStatus::ok);
  CHECK(out.time_ns == hour + 100'000'000);
  CHECK(out.time_ns > before);
  // A receive clock a few minutes off still picks the right hour.
  REQUIRE(decoder.decode(data_packet(100'000), hour - 7 * 60 * kSecond, out) == DecodeStatus::ok);
  CHECK(out.time_ns == hour + 100'000'000);
}

TEST_CASE("hour from GPS: position packet reference, then the rollover", "[decoder][time]") {
  DecoderConfig config;
  PacketDecoder decoder(config);
  // Position packet stamped 3599.5 s past the hour whose fix says 22:59:59 UTC.
  std::array<std::uint8_t, kPositionPacketBytes> bytes{};
  sim::encode_position_packet(3'599'500'000, PpsStatus::locked,
                              sim::make_gprmc(kTopOfHourNs + 3599 * kSecond, true, 48, 11, 0, 0),
                              bytes);
  PositionPacket position;
  REQUIRE(parse_position_packet(bytes, 0, position));
  REQUIRE(decoder.set_gps_time_reference(position));
  DecodedPacket out;
  // Receive times are junk (host clock at the epoch): GPS decides.
  REQUIRE(decoder.decode(data_packet(3'599'900'000), 0, out) == DecodeStatus::ok);
  CHECK(out.time_ns == kTopOfHourNs + 3'599'900'000'000);
  REQUIRE(decoder.decode(data_packet(100'000), 0, out) == DecodeStatus::ok);
  CHECK(out.time_ns == kTopOfHourNs + kHour + 100'000'000);

  // Not locked or void: refused.
  position.pps = PpsStatus::synchronizing;
  CHECK_FALSE(decoder.set_gps_time_reference(position));
  DecoderConfig no_gps;
  no_gps.use_gps_hour = false;
  PacketDecoder host_only(no_gps);
  position.pps = PpsStatus::locked;
  CHECK_FALSE(host_only.set_gps_time_reference(position));
}

TEST_CASE("hour from GPS: explicit top of the hour", "[decoder][time]") {
  PacketDecoder decoder;
  decoder.set_gps_hour_reference(kTopOfHourNs);
  DecodedPacket out;
  REQUIRE(decoder.decode(data_packet(3'599'900'000), 5 * kHour, out) == DecodeStatus::ok);
  CHECK(out.time_ns == kTopOfHourNs + 3'599'900'000'000);
  REQUIRE(decoder.decode(data_packet(100'000), 5 * kHour, out) == DecodeStatus::ok);
  CHECK(out.time_ns == kTopOfHourNs + kHour + 100'000'000);
}

TEST_CASE("sim capture: pcap clock and GPS give the same absolute time", "[decoder][time]") {
  const auto path = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(path);
  const auto payloads = test::read_classic_pcap(*path);
  REQUIRE_FALSE(payloads.position.empty());
  PacketDecoder by_receive_time;
  PacketDecoder by_gps;
  PositionPacket position;
  REQUIRE(parse_position_packet(payloads.position[0].bytes, 0, position));
  REQUIRE(by_gps.set_gps_time_reference(position));
  DecodedPacket a, b;
  REQUIRE(by_receive_time.decode(payloads.data[0].bytes, payloads.data[0].receive_ns, a) ==
          DecodeStatus::ok);
  REQUIRE(by_gps.decode(payloads.data[0].bytes, 0, b) == DecodeStatus::ok);
  CHECK(a.time_ns == kTopOfHourNs + kSecond);  // one second after 22:00:00 UTC
  CHECK(b.time_ns == a.time_ns);
}

TEST_CASE("a GPS hour unlike the host clock's re-bases time by whole hours, once",
          "[decoder][time]") {
  PacketDecoder decoder;
  DecodedPacket out;
  // Host clock five hours and a bit off the sensor's GPS time.
  const std::int64_t host_ns = kTopOfHourNs + 5 * kHour + 1'000'000'000;
  REQUIRE(decoder.decode(data_packet(1'000'000), host_ns, out) == DecodeStatus::ok);
  CHECK(out.time_rebase_ns == 0);
  const std::int64_t before = out.time_ns;
  decoder.set_gps_hour_reference(kTopOfHourNs);
  REQUIRE(decoder.decode(data_packet(1'001'327), host_ns, out) == DecodeStatus::ok);
  CHECK(out.time_ns == kTopOfHourNs + 1'001'327'000);
  CHECK(out.time_rebase_ns == -5 * kHour);
  CHECK(out.time_ns - out.time_rebase_ns - before == 1'327'000);  // the stamps stay continuous
  REQUIRE(decoder.decode(data_packet(1'002'654), host_ns, out) == DecodeStatus::ok);
  CHECK(out.time_rebase_ns == 0);
  // The same reference again moves nothing.
  decoder.set_gps_hour_reference(kTopOfHourNs);
  REQUIRE(decoder.decode(data_packet(1'003'981), host_ns, out) == DecodeStatus::ok);
  CHECK(out.time_rebase_ns == 0);
}

TEST_CASE("time source: host clock, GPS without PPS, GPS with PPS", "[decoder][time]") {
  PacketDecoder decoder;
  DecodedPacket out;
  REQUIRE(decoder.decode(data_packet(1'000'000), kTopOfHourNs, out) == DecodeStatus::ok);
  CHECK(out.time_source == TimeSource::host_clock);
  std::array<std::uint8_t, kPositionPacketBytes> bytes{};
  sim::encode_position_packet(1'000'500'000, PpsStatus::synchronizing,
                              sim::make_gprmc(kTopOfHourNs + kSecond, true, 48, 11, 0, 0), bytes);
  PositionPacket position;
  REQUIRE(parse_position_packet(bytes, 0, position));
  decoder.note_gps_status(position);
  CHECK_FALSE(decoder.set_gps_time_reference(position));  // PPS not locked
  REQUIRE(decoder.decode(data_packet(1'001'327), kTopOfHourNs, out) == DecodeStatus::ok);
  CHECK(out.time_source == TimeSource::gps_no_pps);
  position.pps = PpsStatus::locked;
  decoder.note_gps_status(position);
  REQUIRE(decoder.set_gps_time_reference(position));
  REQUIRE(decoder.decode(data_packet(1'002'654), kTopOfHourNs, out) == DecodeStatus::ok);
  CHECK(out.time_source == TimeSource::gps_pps);
  CHECK(to_string(out.time_source) == "gps_pps");
  position.pps = PpsStatus::absent;  // PPS lost: the sensor clock free-runs again
  decoder.note_gps_status(position);
  REQUIRE(decoder.decode(data_packet(1'003'981), kTopOfHourNs, out) == DecodeStatus::ok);
  CHECK(out.time_source == TimeSource::gps_no_pps);
}

TEST_CASE("time base: a free-running sensor clock is blended onto the host clock, continuous",
          "[decoder][time]") {
  // No GPS: the sensor counts from power-on (stamps from 5 s), the host clock says 22:17.
  PacketDecoder decoder;
  DecodedPacket out;
  constexpr std::int64_t kPeriod = 1'327'104;  // ns, one packet (rounded to the us stamps)
  const std::int64_t host0 = kTopOfHourNs + 17 * 60 * kSecond + 123'456'789;
  std::uint32_t stamp = 5'000'000;
  REQUIRE(decoder.decode(data_packet(stamp), host0, out) == DecodeStatus::ok);
  CHECK(out.time_ns == host0);  // on the host clock from the first packet
  CHECK(out.time_source == TimeSource::host_clock);
  std::int64_t previous = out.time_ns;
  std::int64_t worst_step_error = 0;
  // The host clock runs 100 ppm fast against the sensor and jitters by up to 0.3 ms.
  for (int k = 1; k <= 20'000; ++k) {
    stamp += 1327;
    const std::int64_t jitter = ((k * 7919) % 600 - 300) * 1000;
    const std::int64_t host = host0 + k * kPeriod + k * kPeriod / 10'000 + jitter;
    REQUIRE(decoder.decode(data_packet(stamp), host, out) == DecodeStatus::ok);
    const std::int64_t step = out.time_ns - previous;
    worst_step_error = std::max(worst_step_error, std::abs(step - 1'327'000));
    previous = out.time_ns;
  }
  CHECK(worst_step_error <= 1'000);  // the sensor's steps, at most 1 us of slew per packet
  const std::int64_t host_now = host0 + 20'000 * kPeriod + 20'000 * kPeriod / 10'000;
  CHECK(std::abs(out.time_ns - host_now) < 1'000'000);  // drift followed to within 1 ms
}

TEST_CASE("time base: a sensor clock on the host clock keeps its exact stamps",
          "[decoder][time]") {
  PacketDecoder decoder;
  DecodedPacket out;
  for (int k = 0; k < 100; ++k) {
    const std::uint32_t stamp = 1'000'000 + static_cast<std::uint32_t>(k) * 1327;
    // Received 0.4-0.9 ms after the firing: latency, not a clock offset.
    const std::int64_t receive = kTopOfHourNs + std::int64_t{stamp} * 1000 + 400'000 + k * 5'000;
    REQUIRE(decoder.decode(data_packet(stamp), receive, out) == DecodeStatus::ok);
    CHECK(out.time_ns == kTopOfHourNs + std::int64_t{stamp} * 1000);
  }
}
