#include "vlpground/driver/packet_decoder.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "column_decoding.hpp"
#include "le_load.hpp"
#include "packet_layout.hpp"
#include "time_base.hpp"
#include "trig_table.hpp"

namespace vlpground {

struct PacketDecoder::Constants {
  std::array<driver_detail::DecodeConstants, 2> by_model;  // indexed by Model
};

using driver_detail::block_azimuth;
using driver_detail::kBlockBytes;
using driver_detail::kCentidegPerTurn;
using driver_detail::kHourUs;
using driver_detail::kModeOffset;
using driver_detail::kProductOffset;
using driver_detail::kStampOffset;
using driver_detail::load_le16;
using driver_detail::load_le32;
using driver_detail::stamp_gap_us;

namespace {


void clear_last_layer(DecodedPacket& out) {
  out.layer[kLastLayer] = {};
  out.same_echo = {};
}

DecodeStatus check_layout(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kDataPacketBytes) return DecodeStatus::wrong_size;
  // Ask for all of the packet's cache lines at once: fresh packets (a capture read from
  // memory) otherwise arrive one miss at a time, behind the flag checks.
  constexpr std::size_t kCacheLine = 64;
  for (std::size_t at = 0; at < kDataPacketBytes; at += kCacheLine) {
    __builtin_prefetch(bytes.data() + at);
  }
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
      vlp16_(std::make_shared<const SensorModel>(SensorModel::builtin(Model::vlp16))),
      hires_(std::make_shared<const SensorModel>(SensorModel::builtin(Model::hires))),
      constants_(std::make_unique<Constants>()),
      time_base_(std::make_unique<driver_detail::TimeBase>()) {
  config_.validate();
  if (!config_.calibration_file.empty()) {
    // A calibration describes the actual sensor, whatever the packets call it.
    auto calibrated = std::make_shared<const SensorModel>(SensorModel::from_calibration_file(
        config_.calibration_file, config_.force_model.value_or(Model::vlp16)));
    vlp16_ = calibrated;
    hires_ = std::move(calibrated);
  }
  constants_->by_model[static_cast<std::size_t>(Model::vlp16)] =
      driver_detail::DecodeConstants::from(*vlp16_);
  constants_->by_model[static_cast<std::size_t>(Model::hires)] =
      driver_detail::DecodeConstants::from(*hires_);
  (void)driver_detail::TrigTable::instance();  // build the table now, not on the first packet
}

PacketDecoder::~PacketDecoder() = default;
PacketDecoder::PacketDecoder(PacketDecoder&&) noexcept = default;
PacketDecoder& PacketDecoder::operator=(PacketDecoder&&) noexcept = default;

const SensorModel& PacketDecoder::sensor_model(Model m) const { return *calibration(m); }

const std::shared_ptr<const SensorModel>& PacketDecoder::calibration(Model m) const {
  return m == Model::hires ? hires_ : vlp16_;
}

void PacketDecoder::set_gps_hour_reference(std::int64_t top_of_hour_ns) {
  if (!config_.use_gps_hour) return;
  gps_reference_ = true;
  gps_anchor_pending_ = true;
  gps_top_of_hour_ns_ = top_of_hour_ns;
  reference_changed_ = true;
}

bool PacketDecoder::set_gps_time_reference(const PositionPacket& position) {
  if (!config_.use_gps_hour || !position.gprmc.parsed || !position.gprmc.valid ||
      position.pps != PpsStatus::locked || position.stamp_us_past_hour >= kHourUs) {
    return false;
  }
  // The position packet's own stamp counts from the top of the hour nearest its fix time.
  const std::int64_t stamp_ns = std::int64_t{position.stamp_us_past_hour} * 1000;
  gps_anchor_ns_ = driver_detail::nearest_hour_time(stamp_ns, position.gprmc.utc_ns());
  gps_reference_ = true;
  gps_anchor_pending_ = false;
  reference_changed_ = true;
  return true;
}

void PacketDecoder::note_gps_status(const PositionPacket& position) {
  gps_fix_ = position.gprmc.parsed && position.gprmc.valid;
  pps_locked_ = position.pps == PpsStatus::locked;
}

void PacketDecoder::warn_once(bool& raised, ErrorCode code, std::string message) {
  if (raised) return;
  raised = true;
  last_warning_ = std::move(message);
  last_warning_code_ = code;
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
  const std::int64_t gap = stamp_gap_us(previous_stamp_us_, stamp_us);
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
      warn_once(warned_product_, ErrorCode::product_mismatch, text);
    }
  }
  if (config_.force_model) return *config_.force_model;
  return product_byte == kProductHiRes ? Model::hires : Model::vlp16;
}

std::int64_t PacketDecoder::gps_time_ns(std::int64_t stamp_ns) {
  if (gps_anchor_pending_) {
    gps_anchor_pending_ = false;
    gps_anchor_ns_ = gps_top_of_hour_ns_ + stamp_ns;
    return gps_anchor_ns_;
  }
  // Nearest to the latest GPS-clock time known: the stamp wrap at the top of the hour then
  // moves to the next hour, keeping time monotonic.
  gps_anchor_ns_ = driver_detail::nearest_hour_time(stamp_ns, gps_anchor_ns_);
  return gps_anchor_ns_;
}

DecodeStatus PacketDecoder::decode(std::span<const std::uint8_t> bytes, std::int64_t receive_ns,
                                   DecodedPacket& out, std::int64_t stamp_offset_ns) {
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
      warn_once(warned_not_vlp16_, ErrorCode::wrong_sensor, text);
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
  // Continuous from the first packet: see time_base.hpp (host/sensor blend, GPS take-over).
  const std::int64_t stamp_ns = std::int64_t{stamp_us} * 1000 + stamp_offset_ns;
  const driver_detail::TimeBase::Placed placed =
      gps_reference_ ? time_base_->on_gps(stamp_ns, gps_time_ns(stamp_ns), reference_changed_)
                     : time_base_->on_host(stamp_ns, receive_ns);
  reference_changed_ = false;
  out.time_ns = placed.time_ns;
  out.time_rebase_ns = placed.rebase_ns;
  out.time_source = gps_reference_ && pps_locked_ ? TimeSource::gps_pps
                    : gps_fix_                    ? TimeSource::gps_no_pps
                                                  : TimeSource::host_clock;
  out.first_azimuth_centideg = static_cast<std::uint16_t>(block_azimuth(p));
  out.column_count = dual ? kBlocksPerPacket : kMaxColumnsPerPacket;
  driver_detail::decode_columns(p, constants_->by_model[static_cast<std::size_t>(out.model)], dual,
                                out.time_ns, out);
  ++counters_.decoded;
  return DecodeStatus::ok;
}

}  // namespace vlpground
