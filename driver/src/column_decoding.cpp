#include "column_decoding.hpp"

#include <cmath>
#include <numbers>

#include "le_load.hpp"
#include "packet_layout.hpp"
#include "trig_table.hpp"
#include "vlpground_internal/vector_clones.hpp"

namespace vlpground::driver_detail {

namespace {

constexpr std::size_t kRecordBytes = 3;
constexpr std::size_t kFlagAndAzimuthBytes = 4;
constexpr std::size_t kHalfBlockBytes = 16 * kRecordBytes;  // second firing sequence of a block
constexpr float kRadPerCentideg = std::numbers::pi_v<float> / 18000.f;
// Laser k fires k * 2.304 us into a sequence; two sequences (110.592 us) span one block gap.
constexpr double kLaserStepOfGap =
    static_cast<double>(kFiringIntervalNs) / static_cast<double>(2 * kSequencePeriodNs);

// Signed azimuth step from `from` to `to` in centidegrees, across the 0/360 wrap.
int azimuth_step(int from, int to) {
  int d = to - from;
  if (d < -kCentidegPerTurn / 2) d += kCentidegPerTurn;
  if (d > kCentidegPerTurn / 2) d -= kCentidegPerTurn;
  return d;
}

// Where each column's records start and how its azimuth runs over its 16 lasers.
struct ColumnPlan {
  // Byte offset of channel 0's record of the column in the packet.
  std::array<std::int32_t, kMaxColumnsPerPacket> primary;             // strongest / only return
  std::array<std::int32_t, kMaxColumnsPerPacket> last;                // dual: last return
  alignas(16) std::array<float, kMaxColumnsPerPacket> base_centideg;  // laser 0's azimuth
  alignas(16) std::array<float, kMaxColumnsPerPacket> step_centideg;  // added per laser
  alignas(16) std::array<float, kMaxColumnsPerPacket> cos, sin;       // of the current laser
  alignas(16) std::array<float, kMaxColumnsPerPacket> cos_step, sin_step;
};

// Gap (centidegrees) from each block group to the next, `stride` blocks apart (1 single,
// 2 dual pairs). The last group has no successor in the packet: it gets the mean rate over
// the packet (the manual's advice), never zero.
std::array<double, kBlocksPerPacket> azimuth_gaps(const std::array<int, kBlocksPerPacket>& az,
                                                  int stride) {
  std::array<double, kBlocksPerPacket> gap{};
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
  return gap;
}

// cos and sin of a small angle (|x| <= 0.07 rad) by series: exact to double precision.
CosSin small_angle(double x) {
  const double x2 = x * x;
  return {1.0 - x2 * (0.5 - x2 * (1.0 / 24.0 - x2 / 720.0)),
          x * (1.0 - x2 * (1.0 / 6.0 - x2 / 120.0))};
}

// Column `c` of a group: channel 16 (the group's second column) fires 55.296 us, half the
// block gap, after channel 0.
void plan_column(std::size_t c, std::size_t group, int half, bool dual, double base_centideg,
                 const CosSin& base, double gap, ColumnPlan& plan) {
  const std::size_t half_offset =
      kFlagAndAzimuthBytes + static_cast<std::size_t>(half) * kHalfBlockBytes;
  plan.primary[c] =
      static_cast<std::int32_t>((dual ? group + 1 : group) * kBlockBytes + half_offset);
  plan.last[c] = static_cast<std::int32_t>(group * kBlockBytes + half_offset);
  const double step = gap * kLaserStepOfGap;
  const CosSin step_cs = small_angle(step * static_cast<double>(kRadPerCentideg));
  plan.base_centideg[c] = static_cast<float>(base_centideg);
  plan.step_centideg[c] = static_cast<float>(step);
  plan.cos[c] = static_cast<float>(base.cos);
  plan.sin[c] = static_cast<float>(base.sin);
  plan.cos_step[c] = static_cast<float>(step_cs.cos);
  plan.sin_step[c] = static_cast<float>(step_cs.sin);
}

// Single: block b holds sequences 2b and 2b+1. Dual: pair (b, b+1), b even, holds sequences
// b and b+1; the even block is the last return, the odd block the strongest.
void plan_columns(const std::uint8_t* p, bool dual, int count, ColumnPlan& plan) {
  std::array<int, kBlocksPerPacket> az{};
  for (std::size_t b = 0; b < az.size(); ++b) az[b] = block_azimuth(p + b * kBlockBytes);
  const auto gap = azimuth_gaps(az, dual ? 2 : 1);
  const auto& trig = TrigTable::instance();
  constexpr double kSeriesLimitCentideg = 500.0;  // half of it is 0.044 rad
  for (std::size_t c = 0; c < static_cast<std::size_t>(count); c += 2) {
    const std::size_t group = dual ? c : c / 2;
    const CosSin first = trig.at(az[group]);
    plan_column(c, group, 0, dual, az[group], first, gap[group], plan);
    const double second_centideg = wrap_centideg(az[group] + 0.5 * gap[group]);
    CosSin second;
    if (std::abs(gap[group]) <= kSeriesLimitCentideg) {
      const CosSin d = small_angle(0.5 * gap[group] * static_cast<double>(kRadPerCentideg));
      second = {first.cos * d.cos - first.sin * d.sin, first.sin * d.cos + first.cos * d.sin};
    } else {
      second = trig.at(second_centideg);
    }
    plan_column(c + 1, group, 1, dual, second_centideg, second, gap[group], plan);
  }
}

// The 3-byte records of laser `k` in every column, each read as one 32-bit word (distance
// in the low 16 bits, intensity above; the byte after is ignored). Reading whole words
// halves the scalar work of the gather, the one part of the decode that cannot vectorise
// on the x86-64 baseline. The last record of a packet starts 9 bytes before its end.
template <std::size_t N>
void gather_records(const std::uint8_t* p, const std::int32_t* offset, std::size_t k,
                    std::uint16_t* __restrict raw, std::uint8_t* __restrict intensity) {
  std::array<std::uint32_t, N> word;
  const std::uint8_t* records = p + k * kRecordBytes;
  for (std::size_t c = 0; c < N; ++c) word[c] = load_le32(records + offset[c]);
  for (std::size_t c = 0; c < N; ++c) {
    raw[c] = static_cast<std::uint16_t>(word[c]);
    intensity[c] = static_cast<std::uint8_t>(word[c] >> 16);
  }
}

// Sensor frame, x forward, y left, z up (manual): x = R cos(w) cos(a), y = -R cos(w) sin(a),
// z = R sin(w) + vertical offset, a = azimuth + rotational correction. No return: all zero.
template <std::size_t N>
void emit_row(const std::uint16_t* __restrict raw, const float* __restrict cos_a,
              const float* __restrict sin_a, const DecodeConstants& constants, std::size_t k,
              PacketLayer& out) {
  const float resolution = constants.resolution_m;
  const float correction = constants.distance_correction_m[k];
  const float cos_w = constants.cos_elevation[k];
  const float sin_w = constants.sin_elevation[k];
  const float offset = constants.vertical_offset_m[k];
  float* __restrict distance = out.distance_m[k].data();
  float* __restrict x = out.x_m[k].data();
  float* __restrict y = out.y_m[k].data();
  float* __restrict z = out.z_m[k].data();
  for (std::size_t c = 0; c < N; ++c) {
    const float hit = raw[c] != 0 ? 1.f : 0.f;
    const float r = (static_cast<float>(raw[c]) * resolution + correction) * hit;
    const float horizontal = r * cos_w;
    distance[c] = r;
    x[c] = horizontal * cos_a[c];
    y[c] = -horizontal * sin_a[c];
    z[c] = (r * sin_w + offset) * hit;
  }
}

// Azimuths of laser `k` in degrees, [0, 360).
template <std::size_t N>
void emit_azimuths(const ColumnPlan& plan, std::size_t k, float* __restrict out) {
  const auto fk = static_cast<float>(k);
  constexpr auto kTurn = static_cast<float>(kCentidegPerTurn);
  for (std::size_t c = 0; c < N; ++c) {
    float a = plan.base_centideg[c] + fk * plan.step_centideg[c];
    // Arithmetic instead of branches so that the loop vectorises.
    a += kTurn * (static_cast<float>(a < 0.f) - static_cast<float>(a >= kTurn));
    out[c] = a * 0.01f;
  }
}

template <std::size_t N>
void same_echo_row(const std::uint16_t* __restrict strongest, const std::uint16_t* __restrict last,
                   const std::uint8_t* __restrict strongest_intensity,
                   const std::uint8_t* __restrict last_intensity, std::uint8_t* __restrict out) {
  for (std::size_t c = 0; c < N; ++c) {
    out[c] = static_cast<std::uint8_t>(last[c] != 0 && last[c] == strongest[c] &&
                                       last_intensity[c] == strongest_intensity[c]);
  }
}

// cos/sin of laser k's azimuth plus its rotational correction, per column.
template <std::size_t N>
void rotate_row(const ColumnPlan& plan, float cos_rotation, float sin_rotation,
                float* __restrict cos_a, float* __restrict sin_a) {
  for (std::size_t c = 0; c < N; ++c) {
    cos_a[c] = plan.cos[c] * cos_rotation - plan.sin[c] * sin_rotation;
    sin_a[c] = plan.sin[c] * cos_rotation + plan.cos[c] * sin_rotation;
  }
}

// From laser k's azimuth to laser k + 1's: one complex product per column.
template <std::size_t N>
void advance_row(ColumnPlan& plan) {
  for (std::size_t c = 0; c < N; ++c) {
    const float next_cos = plan.cos[c] * plan.cos_step[c] - plan.sin[c] * plan.sin_step[c];
    plan.sin[c] = plan.sin[c] * plan.cos_step[c] + plan.cos[c] * plan.sin_step[c];
    plan.cos[c] = next_cos;
  }
}

template <std::size_t N, bool kDual>
void decode_rows(const std::uint8_t* p, const DecodeConstants& constants, ColumnPlan& plan,
                 DecodedPacket& out) {
  alignas(16) std::array<std::uint16_t, kMaxColumnsPerPacket> raw, raw_last;
  alignas(16) std::array<float, kMaxColumnsPerPacket> cos_a, sin_a;
  PacketLayer& strongest = out.layer[kStrongestLayer];
  PacketLayer& last = out.layer[kLastLayer];
  for (std::size_t k = 0; k < static_cast<std::size_t>(kLasers); ++k) {
    rotate_row<N>(plan, constants.cos_rotation[k], constants.sin_rotation[k], cos_a.data(),
                  sin_a.data());
    gather_records<N>(p, plan.primary.data(), k, raw.data(), strongest.intensity[k].data());
    emit_row<N>(raw.data(), cos_a.data(), sin_a.data(), constants, k, strongest);
    if constexpr (kDual) {
      gather_records<N>(p, plan.last.data(), k, raw_last.data(), last.intensity[k].data());
      emit_row<N>(raw_last.data(), cos_a.data(), sin_a.data(), constants, k, last);
      same_echo_row<N>(raw.data(), raw_last.data(), strongest.intensity[k].data(),
                       last.intensity[k].data(), out.same_echo[k].data());
    }
    emit_azimuths<N>(plan, k, out.azimuth_deg[k].data());
    advance_row<N>(plan);
  }
}

}  // namespace

int block_azimuth(const std::uint8_t* block) {
  const int raw = load_le16(block + 2);
  return raw == kCentidegPerTurn ? 0 : raw;
}

DecodeConstants DecodeConstants::from(const SensorModel& model) {
  DecodeConstants c;
  c.resolution_m = static_cast<float>(model.distance_resolution_m);
  for (std::size_t k = 0; k < static_cast<std::size_t>(kLasers); ++k) {
    const auto& l = model.lasers[k];
    c.cos_elevation[k] = static_cast<float>(l.cos_elevation);
    c.sin_elevation[k] = static_cast<float>(l.sin_elevation);
    c.vertical_offset_m[k] = static_cast<float>(l.vertical_offset_m);
    c.distance_correction_m[k] = static_cast<float>(l.distance_correction_m);
    c.cos_rotation[k] = static_cast<float>(l.cos_azimuth_offset);
    c.sin_rotation[k] = static_cast<float>(l.sin_azimuth_offset);
  }
  return c;
}

VLPGROUND_VECTOR_CLONES
void decode_columns(const std::uint8_t* p, const DecodeConstants& constants, bool dual,
                    std::int64_t time0_ns, DecodedPacket& out) {
  const int count = dual ? kBlocksPerPacket : kMaxColumnsPerPacket;
  out.column_count = count;
  for (int c = 0; c < count; ++c) {
    out.column_time_ns[static_cast<std::size_t>(c)] = time0_ns + c * kSequencePeriodNs;
  }
  ColumnPlan plan;
  plan_columns(p, dual, count, plan);
  if (dual) {
    decode_rows<kBlocksPerPacket, true>(p, constants, plan, out);
  } else {
    decode_rows<kMaxColumnsPerPacket, false>(p, constants, plan, out);
  }
}

}  // namespace vlpground::driver_detail
