#include "loop_seam.hpp"

#include <algorithm>
#include <cmath>

#include "azimuth_math.hpp"
#include "column_decoding.hpp"
#include "le_load.hpp"
#include "packet_layout.hpp"
#include "vlpground/types.hpp"

namespace vlpground::driver_detail {
namespace {

constexpr std::size_t kLastBlockOffset = 11 * kBlockBytes;
constexpr double kMaxPacketStepDeg = 30.0;  // 24 firings at 1200 rpm sweep ~9.6 deg

// Azimuth of the block at `offset` in degrees, or -1 when not a valid block.
double block_deg(std::span<const std::uint8_t> p, std::size_t offset) {
  if (p.size() < 1206 || p[offset] != 0xFF || p[offset + 1] != 0xEE) return -1.0;
  if (load_le16(p.data() + offset + 2) > 36000) return -1.0;
  return block_azimuth(p.data() + offset) / 100.0;
}

}  // namespace

void LoopSeam::note_data(std::span<const std::uint8_t> payload, std::int64_t record_ns) {
  const double first = block_deg(payload, 0);
  const double final = block_deg(payload, kLastBlockOffset);
  if (first < 0 || final < 0) return;  // malformed: the decoder counts it
  if (have_data_) {
    const double step = forward_deg(last_first_deg_, first);
    if (step > 0 && step < kMaxPacketStepDeg) {
      step_deg_ = step;
      if (first_pass_) covered_deg_ += step;
    }
  } else {
    first_stamp_us_ = load_le32(payload.data() + kStampOffset);
  }
  have_data_ = true;
  last_stamp_us_ = load_le32(payload.data() + kStampOffset);
  last_record_ns_ = record_ns;
  last_first_deg_ = first;
  last_final_deg_ = final;
  dual_ = payload[kModeOffset] == kModeDual;
}

void LoopSeam::end_pass(std::int64_t first_record_ns, std::int64_t last_record_ns,
                        std::uint64_t records) {
  if (first_pass_) joinable_ = step_deg_ > 0 && covered_deg_ >= 360.0 + 2 * step_deg_;
  first_pass_ = false;
  if (joinable_ && have_data_) {
    joining_ = true;  // the shifts are set by the packet where the rotation continues
    skipped_ = 0;
    return;
  }
  // Not joinable: the next pass follows this one in time.
  const std::int64_t span_ns = last_record_ns - first_record_ns;
  const std::int64_t gap_ns =
      records > 1 ? span_ns / static_cast<std::int64_t>(records - 1) : 0;
  receive_shift_ns_ += std::max<std::int64_t>(span_ns, 0) + std::max<std::int64_t>(gap_ns, 1000);
  if (have_data_) {
    stamp_shift_ns_ += stamp_gap_us(first_stamp_us_, last_stamp_us_) * 1000 +
                       (dual_ ? kDualPacketPeriodNs : kSinglePacketPeriodNs);
  }
}

bool LoopSeam::join_at(std::span<const std::uint8_t> payload, std::int64_t record_ns) {
  const double first = block_deg(payload, 0);
  const bool continues = first >= 0 && forward_deg(last_final_deg_, first) > 0 &&
                         forward_deg(last_final_deg_, first) <= step_deg_;
  // A rotation holds 360 / step packets: past that (packets lost where the rotation would
  // continue), join here rather than skip the whole pass.
  const auto give_up = static_cast<std::uint64_t>(std::ceil(360.0 / step_deg_)) + 2;
  if (!continues && ++skipped_ <= give_up) return false;
  shift_to_follow(load_le32(payload.data() + kStampOffset), record_ns);
  joining_ = false;
  return true;
}

// This packet (stamp, capture stamp) comes one packet period after the previous pass's last.
void LoopSeam::shift_to_follow(std::uint32_t stamp_us, std::int64_t record_ns) {
  const std::int64_t period_ns = dual_ ? kDualPacketPeriodNs : kSinglePacketPeriodNs;
  stamp_shift_ns_ += stamp_gap_us(stamp_us, last_stamp_us_) * 1000 + period_ns;
  receive_shift_ns_ += last_record_ns_ - record_ns + period_ns;
}

}  // namespace vlpground::driver_detail
