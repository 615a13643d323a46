#include "vlpground/driver/packet_decoder.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "le_load.hpp"
#include "trig_table.hpp"

namespace vlpground {

using driver_detail::kCentidegPerTurn;
using driver_detail::load_le16;
using driver_detail::load_le32;

namespace {

constexpr std::size_t kBlockBytes = 100;
constexpr std::size_t kRecordBytes = 3;
constexpr std::size_t kStampOffset = 1200;
constexpr std::size_t kModeOffset = 1204;
constexpr std::size_t kProductOffset = 1205;
constexpr int kChannelsPerBlock = 32;
constexpr std::int64_t kHourNs = 3'600'000'000'000;
constexpr std::int64_t kHourUs = 3'600'000'000;

// Fraction of the block-to-block azimuth gap at which channel `ch` fires (manual):
// (55.296 * (ch / 16) + 2.304 * (ch % 16)) / 110.592, exact in integer ns.
constexpr std::array<double, kChannelsPerBlock> kGapFraction = [] {
  std::array<double, kChannelsPerBlock> f{};
  for (int ch = 0; ch < kChannelsPerBlock; ++ch) {
    const auto ns = kSequencePeriodNs * (ch / 16) + kFiringIntervalNs * (ch % 16);
    f[static_cast<std::size_t>(ch)] =
        static_cast<double>(ns) / static_cast<double>(2 * kSequencePeriodNs);
  }
  return f;
}();

// Azimuth of a block in centidegrees, [0, 36000). Real sensors now and then send 36000
// (seen in VLP-16 and HDL-32E captures): that is 0 degrees, not a malformed packet.
int block_azimuth(const std::uint8_t* block) {
  const int raw = load_le16(block + 2);
  return raw == kCentidegPerTurn ? 0 : raw;
}

// Signed azimuth step from `from` to `to` in centidegrees, across the 0/360 wrap.
int azimuth_step(int from, int to) {
  int d = to - from;
  if (d < -kCentidegPerTurn / 2) d += kCentidegPerTurn;
  if (d > kCentidegPerTurn / 2) d -= kCentidegPerTurn;
  return d;
}

// Gap (centidegrees) from each block group to the next, `stride` blocks apart (1 single,
// 2 dual pairs). The last group has no successor in the packet: it gets the mean rate over
// the packet, never zero (a constant rate within 1.3 ms).
void azimuth_gaps(const std::array<int, kBlocksPerPacket>& az, int stride,
                  std::array<double, kBlocksPerPacket>& gap) {
  int total = 0;
  int steps = 0;
  for (int b = 0; b + stride < kBlocksPerPacket; b += stride) {
    const int step =
        azimuth_step(az[static_cast<std::size_t>(b)], az[static_cast<std::size_t>(b + stride)]);
    gap[static_cast<std::size_t>(b)] = step;
    total += step;
    ++steps;
  }
  gap[static_cast<std::size_t>(kBlocksPerPacket - stride)] = static_cast<double>(total) / steps;
}

// cos/sin of the block azimuth; a laser's azimuth is that plus a small interpolated delta.
struct BlockTrig {
  driver_detail::CosSin cs;
  int centideg;
  bool small_gap;  // the delta is small enough for the series below
};
constexpr int kSmallGapCentideg = 500;
constexpr double kRadPerCentideg = std::numbers::pi / 18000.0;

// cos/sin of (block azimuth + delta): angle addition with a short series for the small delta
// (|delta| <= 5 degrees: truncation error below 1e-12); the table for anything larger.
inline driver_detail::CosSin rotate(const BlockTrig& block, double delta_centideg,
                                    const driver_detail::TrigTable& trig) {
  if (!block.small_gap)
    return trig.at(driver_detail::wrap_centideg(block.centideg + delta_centideg));
  const double d = delta_centideg * kRadPerCentideg;
  const double d2 = d * d;
  const double cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 / 720.0));
  const double sd = d * (1.0 - d2 * (1.0 / 6.0 - d2 / 120.0));
  return {block.cs.cos * cd - block.cs.sin * sd, block.cs.sin * cd + block.cs.cos * sd};
}

// Per-laser constants of the hot loop (all from SensorModel).
struct LaserConsts {
  double cos_w, sin_w, offset_m, cos_rot, sin_rot, resolution_m, correction_m;
};

// Fills laser `k` of `column` for one return of `layer` from a 3-byte record.
inline void fill_return(const std::uint8_t* record, const LaserConsts& c,
                        const driver_detail::CosSin& cs, LaserReturn& out) {
  const std::uint16_t raw = load_le16(record);
  out.intensity = record[2];
  if (raw == 0) {
    out = LaserReturn{0.f, 0.f, 0.f, 0.f, record[2]};
    return;
  }
  // Sensor frame, x forward, y left, z up: x = R cos(w) cos(a), y = -R cos(w) sin(a),
  // z = R sin(w) + vertical offset (manual; a = azimuth + rotational correction).
  const double r = raw * c.resolution_m + c.correction_m;
  const double horizontal = r * c.cos_w;
  out.distance_m = static_cast<float>(r);
  out.x_m = static_cast<float>(horizontal * cs.cos);
  out.y_m = static_cast<float>(-horizontal * cs.sin);
  out.z_m = static_cast<float>(r * c.sin_w + c.offset_m);
}

std::array<LaserConsts, kLasers> laser_consts(const SensorModel& m) {
  std::array<LaserConsts, kLasers> c{};
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto& l = m.lasers[k];
    c[k] = {l.cos_elevation,        l.sin_elevation,      l.vertical_offset_m,
            l.cos_azimuth_offset,   l.sin_azimuth_offset, m.distance_resolution_m,
            l.distance_correction_m};
  }
  return c;
}

// Decodes the columns of a packet. `layer_of_block(b)` says into which return layer block b
// goes; dual pairs share one column pair.
void fill_columns(const std::uint8_t* p, const SensorModel& model, bool dual, std::int64_t time0_ns,
                  DecodedPacket& out) {
  const auto consts = laser_consts(model);
  bool rotated = false;
  for (const auto& c : consts) rotated = rotated || c.sin_rot != 0.0;
  const auto& trig = driver_detail::TrigTable::instance();
  std::array<int, kBlocksPerPacket> az{};
  for (std::size_t b = 0; b < az.size(); ++b) az[b] = block_azimuth(p + b * kBlockBytes);
  const int stride = dual ? 2 : 1;
  std::array<double, kBlocksPerPacket> gap{};
  azimuth_gaps(az, stride, gap);

  for (int b = 0; b < kBlocksPerPacket; b += stride) {
    const auto ub = static_cast<std::size_t>(b);
    // Single: block b holds sequences 2b and 2b+1. Dual: pair (b, b+1) holds sequences b and
    // b+1; the even block is the last return, the odd block the strongest.
    const std::uint8_t* primary = p + (dual ? ub + 1 : ub) * kBlockBytes + 4;
    const std::uint8_t* last = dual ? p + ub * kBlockBytes + 4 : nullptr;
    const int first_sequence = dual ? b : 2 * b;
    const BlockTrig block_trig{trig.at(az[ub]), az[ub], std::abs(gap[ub]) <= kSmallGapCentideg};
    for (int half = 0; half < 2; ++half) {
      const int sequence = first_sequence + half;
      FiringColumn& col = out.columns[static_cast<std::size_t>(sequence)];
      col.time_ns = time0_ns + sequence * kSequencePeriodNs;  // s * 55.296 us
      for (std::size_t k = 0; k < static_cast<std::size_t>(kLasers); ++k) {
        const std::size_t ch = static_cast<std::size_t>(half) * 16 + k;
        const auto& c = consts[k];
        const double delta = gap[ub] * kGapFraction[ch];
        col.azimuth_deg[k] =
            static_cast<float>(driver_detail::wrap_centideg(az[ub] + delta) / 100.0);
        auto cs = rotate(block_trig, delta, trig);
        if (rotated)
          cs = {cs.cos * c.cos_rot - cs.sin * c.sin_rot, cs.sin * c.cos_rot + cs.cos * c.sin_rot};
        const std::size_t at = ch * kRecordBytes;
        fill_return(primary + at, c, cs, col.returns[kStrongestLayer][k]);
        if (last != nullptr) {
          fill_return(last + at, c, cs, col.returns[kLastLayer][k]);
          col.same_echo[k] = static_cast<std::uint8_t>(
              load_le16(last + at) != 0 && load_le16(last + at) == load_le16(primary + at) &&
              last[at + 2] == primary[at + 2]);
        }
      }
    }
  }
}

void clear_last_layer(DecodedPacket& out) {
  for (auto& col : out.columns) {
    col.returns[kLastLayer] = {};
    col.same_echo = {};
  }
}

DecodeStatus check_layout(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kDataPacketBytes) return DecodeStatus::wrong_size;
  for (std::size_t b = 0; b < static_cast<std::size_t>(kBlocksPerPacket); ++b) {
    const std::uint8_t* block = bytes.data() + b * kBlockBytes;
    if (block[0] != 0xFF || block[1] != 0xEE) return DecodeStatus::bad_flag;
    if (load_le16(block + 2) > kCentidegPerTurn) return DecodeStatus::bad_azimuth;
  }
  const std::uint8_t mode = bytes[kModeOffset];
  if (mode != kModeStrongest && mode != kModeLast && mode != kModeDual) {
    return DecodeStatus::unknown_mode;
  }
  return DecodeStatus::ok;
}

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

// The time `stamp_ns` past some top of the hour that lies nearest to `reference_ns`.
std::int64_t nearest_hour_time(std::int64_t stamp_ns, std::int64_t reference_ns) {
  return stamp_ns + floor_div(reference_ns - stamp_ns + kHourNs / 2, kHourNs) * kHourNs;
}

}  // namespace

void DecoderConfig::validate() const {
  if (force_model && *force_model != Model::vlp16 && *force_model != Model::hires) {
    throw std::invalid_argument("DecoderConfig: force_model is not a known model");
  }
  if (!calibration_file.empty()) {
    if (std::FILE* f = std::fopen(calibration_file.c_str(), "r")) {
      std::fclose(f);
    } else {
      throw std::invalid_argument("DecoderConfig: calibration_file '" + calibration_file +
                                  "' cannot be opened");
    }
  }
}

PacketDecoder::PacketDecoder(const DecoderConfig& config)
    : config_(config),
      vlp16_(SensorModel::builtin(Model::vlp16)),
      hires_(SensorModel::builtin(Model::hires)) {
  config_.validate();
  if (!config_.calibration_file.empty()) {
    // A calibration describes the actual sensor, whatever the packets call it.
    const SensorModel calibrated = SensorModel::from_calibration_file(
        config_.calibration_file, config_.force_model.value_or(Model::vlp16));
    vlp16_ = calibrated;
    hires_ = calibrated;
  }
  (void)driver_detail::TrigTable::instance();  // build the table now, not on the first packet
}

const SensorModel& PacketDecoder::sensor_model(Model m) const {
  return m == Model::hires ? hires_ : vlp16_;
}

void PacketDecoder::set_gps_hour_reference(std::int64_t top_of_hour_ns) {
  if (!config_.use_gps_hour) return;
  gps_reference_ = true;
  gps_anchor_pending_ = true;
  gps_top_of_hour_ns_ = top_of_hour_ns;
}

bool PacketDecoder::set_gps_time_reference(const PositionPacket& position) {
  if (!config_.use_gps_hour || !position.gprmc.parsed || !position.gprmc.valid ||
      position.pps != PpsStatus::locked || position.stamp_us_past_hour >= kHourUs) {
    return false;
  }
  // The position packet's own stamp counts from the top of the hour nearest its fix time.
  const std::int64_t stamp_ns = std::int64_t{position.stamp_us_past_hour} * 1000;
  gps_anchor_ns_ = nearest_hour_time(stamp_ns, position.gprmc.utc_ns());
  gps_reference_ = true;
  gps_anchor_pending_ = false;
  return true;
}

void PacketDecoder::warn_once(bool& raised, std::string message) {
  if (raised) return;
  raised = true;
  last_warning_ = std::move(message);
  ++warning_count_;
}

// The VLP-16 family sends a packet every 1327.104 us (single) or 663.552 us (dual) at any
// rpm; the HDL-32E every 552.96 us. Lost packets give multiples; those gaps do not vote.
void PacketDecoder::judge_timing(std::uint32_t stamp_us) {
  if (!have_previous_stamp_) {
    have_previous_stamp_ = true;
    previous_stamp_us_ = stamp_us;
    return;
  }
  std::int64_t gap = std::int64_t{stamp_us} - previous_stamp_us_;
  if (gap < 0) gap += kHourUs;
  previous_stamp_us_ = stamp_us;
  auto near = [gap](std::int64_t period_ns) {
    const std::int64_t d = gap * 1000 - period_ns;
    return d > -20'000 && d < 20'000;
  };
  Family vote = Family::unknown;
  if (near(kSinglePacketPeriodNs) || near(kDualPacketPeriodNs)) vote = Family::vlp16;
  if (near(552'960)) vote = Family::other;
  if (vote == Family::unknown) return;
  run_length_ = vote == run_family_ ? run_length_ + 1 : 1;
  run_family_ = vote;
  if (run_length_ >= 3) family_ = vote;
}

Model PacketDecoder::choose_model(std::uint8_t product_byte) {
  const bool known = product_byte == kProductVlp16 || product_byte == kProductHiRes;
  if (!known) {
    ++counters_.product_mismatch;
    if (!warned_product_) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "product byte 0x%02X is not a VLP-16 family value (0x22 VLP-16, 0x24 Hi-Res)%s;"
                    " decoding as %s",
                    product_byte,
                    family_ == Family::vlp16 ? " but the packet timing is a VLP-16's" : "",
                    to_string(config_.force_model.value_or(Model::vlp16)).data());
      warn_once(warned_product_, text);
    }
  }
  if (config_.force_model) return *config_.force_model;
  return product_byte == kProductHiRes ? Model::hires : Model::vlp16;
}

std::int64_t PacketDecoder::resolve_time_ns(std::uint32_t stamp_us, std::int64_t receive_ns) {
  const std::int64_t stamp_ns = std::int64_t{stamp_us} * 1000;
  if (!gps_reference_) return nearest_hour_time(stamp_ns, receive_ns);
  if (gps_anchor_pending_) {
    gps_anchor_pending_ = false;
    gps_anchor_ns_ = gps_top_of_hour_ns_ + stamp_ns;
    return gps_anchor_ns_;
  }
  // Nearest to the latest GPS-clock time known: the stamp wrap at the top of the hour then
  // moves to the next hour, keeping time monotonic.
  gps_anchor_ns_ = nearest_hour_time(stamp_ns, gps_anchor_ns_);
  return gps_anchor_ns_;
}

DecodeStatus PacketDecoder::decode(std::span<const std::uint8_t> bytes, std::int64_t receive_ns,
                                   DecodedPacket& out) {
  out.packet_index = packets_seen_++;
  out.receive_ns = receive_ns;
  const DecodeStatus layout = check_layout(bytes);
  if (layout != DecodeStatus::ok) {
    out.column_count = 0;
    switch (layout) {
      case DecodeStatus::wrong_size:
        ++counters_.wrong_size;
        break;
      case DecodeStatus::bad_flag:
        ++counters_.bad_flag;
        break;
      case DecodeStatus::bad_azimuth:
        ++counters_.bad_azimuth;
        break;
      default:
        ++counters_.unknown_mode;
        break;
    }
    return layout;
  }
  const std::uint8_t* p = bytes.data();
  const std::uint32_t stamp_us = load_le32(p + kStampOffset);
  judge_timing(stamp_us);
  out.product_byte = p[kProductOffset];
  if (family_ == Family::other) {
    out.column_count = 0;
    ++counters_.not_vlp16;
    if (!warned_not_vlp16_) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "not a VLP-16: packets arrive about 553 us apart (an HDL-32E's spacing; "
                    "product byte 0x%02X); packets are not decoded",
                    out.product_byte);
      warn_once(warned_not_vlp16_, text);
    }
    return DecodeStatus::not_vlp16;
  }
  const std::uint8_t mode_byte = p[kModeOffset];
  const ReturnMode mode = mode_byte == kModeDual   ? ReturnMode::dual
                          : mode_byte == kModeLast ? ReturnMode::last
                                                   : ReturnMode::strongest;
  const bool dual = mode == ReturnMode::dual;
  if (out.mode == ReturnMode::dual && !dual) clear_last_layer(out);
  out.mode = mode;
  out.model = choose_model(out.product_byte);
  out.stamp_us_past_hour = stamp_us;
  out.time_ns = resolve_time_ns(stamp_us, receive_ns);
  out.first_azimuth_centideg = static_cast<std::uint16_t>(block_azimuth(p));
  out.column_count = dual ? kBlocksPerPacket : kMaxColumnsPerPacket;
  fill_columns(p, sensor_model(out.model), dual, out.time_ns, out);
  ++counters_.decoded;
  return DecodeStatus::ok;
}

}  // namespace vlpground
