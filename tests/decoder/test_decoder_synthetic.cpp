// Decoder behaviour on packets built with the project's encoder (vlpground::sim).
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <vector>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/sim/packet_encoder.hpp"

namespace {

using namespace vlpground;
using Bytes = std::array<std::uint8_t, kDataPacketBytes>;

sim::DataPacketFields ramp_fields(int first_centideg, int step, std::uint8_t mode) {
  sim::DataPacketFields f;
  f.return_mode = mode;
  f.stamp_us_past_hour = 1'000'000;
  for (std::size_t b = 0; b < 12; ++b) {
    const int block_step = mode == kModeDual ? static_cast<int>(b / 2) : static_cast<int>(b);
    f.azimuth_centideg[b] =
        static_cast<std::uint16_t>((first_centideg + step * block_step) % 36000);
    for (std::size_t ch = 0; ch < 32; ++ch) {
      f.distance_2mm[b][ch] = static_cast<std::uint16_t>(1000 + 37 * b + 5 * ch);  // ~2 m +
      f.reflectivity[b][ch] = static_cast<std::uint8_t>(b * 32 + ch);
    }
  }
  return f;
}

Bytes encode(const sim::DataPacketFields& f) {
  Bytes bytes{};
  sim::encode_data_packet(f, bytes);
  return bytes;
}

// Manual: fraction of the block gap at which channel `ch` fires.
double gap_fraction(int ch) { return (55.296 * (ch / 16) + 2.304 * (ch % 16)) / 110.592; }

}  // namespace

TEST_CASE("round trip: encoded fields come back with manual geometry", "[decoder]") {
  const auto fields = ramp_fields(12'345, 40, kModeStrongest);
  PacketDecoder decoder;
  DecodedPacket out;
  REQUIRE(decoder.decode(encode(fields), 0, out) == DecodeStatus::ok);
  REQUIRE(out.column_count == 24);
  CHECK(out.stamp_us_past_hour == 1'000'000);
  CHECK(out.first_azimuth_centideg == 12'345);
  const auto& model = decoder.sensor_model(Model::vlp16);
  for (int b = 0; b < 12; ++b) {
    for (int ch = 0; ch < 32; ++ch) {
      const int column = 2 * b + ch / 16;
      const int k = ch % 16;
      const LaserReturn r = out.at(kStrongestLayer, column, k);
      const auto ub = static_cast<std::size_t>(b);
      const auto uch = static_cast<std::size_t>(ch);
      const double range = fields.distance_2mm[ub][uch] * 0.002;
      const double azimuth = (12'345 + 40 * b + 40 * gap_fraction(ch)) / 100.0;
      const double w = model.lasers[static_cast<std::size_t>(k)].elevation_deg * M_PI / 180.0;
      const double a = azimuth * M_PI / 180.0;
      CHECK(r.distance_m == Approx(range).margin(1e-6));
      CHECK(r.intensity == fields.reflectivity[ub][uch]);
      CHECK(out.azimuth(column, k) == Approx(azimuth).margin(1e-4));
      CHECK(r.x_m == Approx(range * std::cos(w) * std::cos(a)).margin(1e-5));
      CHECK(r.y_m == Approx(-range * std::cos(w) * std::sin(a)).margin(1e-5));
      CHECK(r.z_m == Approx(range * std::sin(w) +
                            model.lasers[static_cast<std::size_t>(k)].vertical_offset_m)
                         .margin(1e-5));
      CHECK(out.at(kLastLayer, column, k).distance_m == 0.f);
    }
  }
  // Firing times: the column is laser 0 of sequence s = 2b + ch/16, 55.296 us apart.
  for (std::size_t s = 1; s < 24; ++s) {
    CHECK(out.column_time_ns[s] - out.column_time_ns[0] == static_cast<std::int64_t>(s) * 55'296);
  }
}

TEST_CASE("azimuth wraps at 0 degrees without losing records", "[decoder]") {
  const auto fields = ramp_fields(35'900, 40, kModeStrongest);  // blocks 35900 .. 340 (wrapped)
  PacketDecoder decoder;
  DecodedPacket out;
  REQUIRE(decoder.decode(encode(fields), 0, out) == DecodeStatus::ok);
  double previous = -1.0;
  int crossings = 0;
  for (int s = 0; s < out.column_count; ++s) {
    for (int k = 0; k < 16; ++k) {
      const double a = out.azimuth(s, k);
      CHECK(a >= 0.0);
      CHECK(a < 360.0);
      CHECK(out.at(kStrongestLayer, s, k).distance_m > 0.f);
      if (previous >= 0.0) {
        const double step = a - previous + (a < previous ? 360.0 : 0.0);
        crossings += a < previous ? 1 : 0;
        CHECK(step > 0.0);  // 0.0083 deg between lasers, 0.075 deg between sequences
        CHECK(step < 0.1);
      }
      previous = a;
    }
  }
  CHECK(crossings == 1);
  // Block 2 (359.80 deg) interpolates across the wrap with its 40-centidegree gap.
  CHECK(out.azimuth(5, 15) ==
        Approx((35'980 + 40 * gap_fraction(31)) / 100.0 - 360.0).margin(1e-4));
}

TEST_CASE("last block uses the packet's mean rate, never a zero gap", "[decoder]") {
  auto fields = ramp_fields(1'000, 40, kModeStrongest);
  fields.azimuth_centideg[11] = static_cast<std::uint16_t>(1'000 + 10 * 40 + 45);  // uneven
  PacketDecoder decoder;
  DecodedPacket out;
  REQUIRE(decoder.decode(encode(fields), 0, out) == DecodeStatus::ok);
  const double mean_gap = (fields.azimuth_centideg[11] - fields.azimuth_centideg[0]) / 11.0;
  for (int ch = 0; ch < 32; ++ch) {
    CHECK(out.azimuth(22 + ch / 16, ch % 16) ==
          Approx((fields.azimuth_centideg[11] + mean_gap * gap_fraction(ch)) / 100.0).margin(1e-4));
  }
  CHECK(out.azimuth(23, 15) > out.azimuth(22, 0) + 0.3);
}

TEST_CASE("dual return: even block is last, odd strongest, timing per pair", "[decoder]") {
  auto fields = ramp_fields(20'000, 40, kModeDual);
  // Pair 0 channel 3: the same echo in both blocks; pair 1 channel 0: a single echo missing
  // from neither; other records differ between the blocks (ramp_fields).
  fields.distance_2mm[1][3] = fields.distance_2mm[0][3];
  fields.reflectivity[1][3] = fields.reflectivity[0][3];
  PacketDecoder decoder;
  DecodedPacket out;
  REQUIRE(decoder.decode(encode(fields), 0, out) == DecodeStatus::ok);
  REQUIRE(out.mode == ReturnMode::dual);
  REQUIRE(out.column_count == 12);
  for (int pair = 0; pair < 6; ++pair) {
    const auto even = static_cast<std::size_t>(2 * pair);
    for (int ch = 0; ch < 32; ++ch) {
      const int s = 2 * pair + ch / 16;  // s = (b - b%2) + ch/16
      const int k = ch % 16;
      const auto uch = static_cast<std::size_t>(ch);
      CHECK(out.column_time_ns[static_cast<std::size_t>(s)] - out.column_time_ns[0] ==
            static_cast<std::int64_t>(s) * 55'296);
      CHECK(out.at(kLastLayer, s, k).distance_m ==
            Approx(fields.distance_2mm[even][uch] * 0.002).margin(1e-6));
      CHECK(out.at(kStrongestLayer, s, k).distance_m ==
            Approx(fields.distance_2mm[even + 1][uch] * 0.002).margin(1e-6));
      CHECK(out.at(kLastLayer, s, k).intensity == fields.reflectivity[even][uch]);
      // Both layers share the azimuth; the gap is to the next pair (40 centidegrees).
      const double gap = 40.0;
      CHECK(out.azimuth(s, k) ==
            Approx((20'000 + 40 * pair + gap * gap_fraction(ch)) / 100.0).margin(1e-4));
      CHECK(out.same_echo[static_cast<std::size_t>(k)][static_cast<std::size_t>(s)] ==
            ((pair == 0 && ch == 3) ? 1 : 0));
    }
  }
}

TEST_CASE("azimuth 36000, sent by real sensors, is 0 degrees", "[decoder]") {
  auto fields = ramp_fields(35'960, 40, kModeStrongest);
  PacketDecoder decoder;
  DecodedPacket reference, out;
  REQUIRE(decoder.decode(encode(fields), 0, reference) == DecodeStatus::ok);
  fields.azimuth_centideg[1] = 36'000;  // instead of 0
  REQUIRE(decoder.decode(encode(fields), 0, out) == DecodeStatus::ok);
  for (int s = 0; s < 24; ++s) {
    for (int k = 0; k < 16; ++k) {
      CHECK(out.azimuth(s, k) == reference.azimuth(s, k));
      CHECK(out.at(0, s, k).x_m == reference.at(0, s, k).x_m);
    }
  }
}

TEST_CASE("single return after dual clears the last-return layer", "[decoder]") {
  PacketDecoder decoder;
  DecodedPacket out;
  REQUIRE(decoder.decode(encode(ramp_fields(0, 40, kModeDual)), 0, out) == DecodeStatus::ok);
  REQUIRE(out.at(kLastLayer, 0, 0).distance_m > 0.f);
  REQUIRE(decoder.decode(encode(ramp_fields(0, 40, kModeLast)), 0, out) == DecodeStatus::ok);
  CHECK(out.mode == ReturnMode::last);
  for (int s = 0; s < out.column_count; ++s) {
    for (int k = 0; k < 16; ++k) {
      CHECK(out.at(kLastLayer, s, k).distance_m == 0.f);
      CHECK(out.same_echo[static_cast<std::size_t>(k)][static_cast<std::size_t>(s)] == 0);
      CHECK(out.at(kStrongestLayer, s, k).distance_m > 0.f);  // the only return: layer 0
    }
  }
}

TEST_CASE("malformed packets are statuses and counters", "[decoder]") {
  const Bytes good = encode(ramp_fields(100, 40, kModeStrongest));
  PacketDecoder decoder;
  DecodedPacket out;
  const std::vector<std::uint8_t> shorter(good.begin(), good.end() - 1);
  std::vector<std::uint8_t> longer(good.begin(), good.end());
  longer.push_back(0);
  Bytes bad_flag = good;
  bad_flag[7 * 100 + 1] = 0xDD;
  Bytes bad_mode = good;
  bad_mode[1204] = 0x40;
  Bytes bad_azimuth = good;
  bad_azimuth[3 * 100 + 2] = 0xA1;  // 36001 = 0x8CA1
  bad_azimuth[3 * 100 + 3] = 0x8C;
  CHECK(decoder.decode(shorter, 0, out) == DecodeStatus::wrong_size);
  CHECK(decoder.decode(longer, 0, out) == DecodeStatus::wrong_size);
  CHECK(decoder.decode({}, 0, out) == DecodeStatus::wrong_size);
  CHECK(decoder.decode(bad_flag, 0, out) == DecodeStatus::bad_flag);
  CHECK(decoder.decode(bad_mode, 0, out) == DecodeStatus::unknown_mode);
  CHECK(decoder.decode(bad_azimuth, 0, out) == DecodeStatus::bad_azimuth);
  CHECK(out.column_count == 0);
  CHECK(decoder.decode(good, 0, out) == DecodeStatus::ok);
  CHECK(out.packet_index == 6);  // every packet given to decode() counts
  const auto& c = decoder.counters();
  CHECK(c.wrong_size == 3);
  CHECK(c.bad_flag == 1);
  CHECK(c.unknown_mode == 1);
  CHECK(c.bad_azimuth == 1);
  CHECK(c.decoded == 1);
  CHECK(decoder.warning_count() == 0);
}

TEST_CASE("product byte 0x21 with VLP-16 timing warns once and decodes", "[decoder]") {
  PacketDecoder decoder;
  DecodedPacket out;
  auto fields = ramp_fields(0, 40, kModeStrongest);
  fields.product = 0x21;
  for (int i = 0; i < 10; ++i) {
    fields.stamp_us_past_hour = static_cast<std::uint32_t>(1'000'000 + i * 1327);
    REQUIRE(decoder.decode(encode(fields), 0, out) == DecodeStatus::ok);
    CHECK(out.model == Model::vlp16);
  }
  CHECK(decoder.counters().product_mismatch == 10);
  CHECK(decoder.warning_count() == 1);
  CHECK(decoder.last_warning().find("0x21") != std::string::npos);
}

TEST_CASE("product byte selects the model unless forced", "[decoder]") {
  auto fields = ramp_fields(0, 40, kModeStrongest);
  fields.product = kProductHiRes;
  DecodedPacket out;
  PacketDecoder by_byte;
  REQUIRE(by_byte.decode(encode(fields), 0, out) == DecodeStatus::ok);
  CHECK(out.model == Model::hires);
  DecoderConfig config;
  config.force_model = Model::vlp16;
  PacketDecoder forced(config);
  REQUIRE(forced.decode(encode(fields), 0, out) == DecodeStatus::ok);
  CHECK(out.model == Model::vlp16);
  CHECK(forced.counters().product_mismatch == 0);
  // Laser 0 at -15 deg (VLP-16), not -10 deg (Hi-Res).
  const LaserReturn r = out.at(kStrongestLayer, 0, 0);
  CHECK(std::asin((r.z_m - 0.0112) / r.distance_m) * 180.0 / M_PI == Approx(-15.0).margin(1e-3));
}

TEST_CASE("553 us packet spacing is not a VLP-16", "[decoder]") {
  PacketDecoder decoder;
  DecodedPacket out;
  auto fields = ramp_fields(0, 40, kModeStrongest);
  fields.product = 0x21;
  int refused = 0;
  for (int i = 0; i < 20; ++i) {
    fields.stamp_us_past_hour = static_cast<std::uint32_t>(5'000 + i * 553);
    refused += decoder.decode(encode(fields), 0, out) == DecodeStatus::not_vlp16 ? 1 : 0;
  }
  CHECK(refused >= 16);
  CHECK(decoder.counters().not_vlp16 == static_cast<std::uint64_t>(refused));
  CHECK(decoder.last_warning().find("not a VLP-16") != std::string::npos);
  CHECK(decoder.warning_count() == 2);  // unknown product byte, then not a VLP-16
}
