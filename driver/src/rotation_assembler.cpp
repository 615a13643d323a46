#include "vlpground/driver/rotation_assembler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "azimuth_math.hpp"
#include "packet_run_copy.hpp"

namespace vlpground {

using driver_detail::forward_deg;
using driver_detail::wrap_deg;

struct RotationAssembler::ColumnSource {
  const DecodedPacket* packet = nullptr;  // nullptr: a lost / outside-FOV column
  std::int64_t time_ns = 0;
  double azimuth_deg = 0.0;
  std::uint64_t packet_index = kNoPacketIndex;
  std::uint8_t in_packet = kNoColumnInPacket;
  bool outside_fov = false;
};

namespace {

std::int64_t packet_period_ns(ReturnMode mode) {
  return mode == ReturnMode::dual ? kDualPacketPeriodNs : kSinglePacketPeriodNs;
}

// The manual's ring order: even laser l -> ring l/2, odd laser l -> ring 8 + (l-1)/2.
std::array<std::uint8_t, kLasers> default_laser_of_ring() {
  std::array<std::uint8_t, kLasers> out{};
  for (int ring = 0; ring < kLasers; ++ring) {
    out[static_cast<std::size_t>(ring)] =
        static_cast<std::uint8_t>(ring < 8 ? 2 * ring : 2 * (ring - 8) + 1);
  }
  return out;
}

// Largest azimuth step between consecutive firings judged as rotation (10 deg is ~30 times
// the step at 1200 rpm), and the backward step tolerated as encoder jitter.
constexpr double kMaxColumnStepDeg = 10.0;
constexpr double kJitterDeg = 0.5;
// A silent FOV sector filled in one push must leave room so the cut is crossed at most once.
constexpr double kMaxFovGapDeg = 300.0;

double rpm_from_rate(double deg_per_ns) { return deg_per_ns * 1e9 * 60.0 / 360.0; }

}  // namespace

void AssemblerConfig::validate() const {
  if (!(cut_angle_deg >= 0.0 && cut_angle_deg < 360.0)) {
    throw std::invalid_argument("assembler: cut_angle_deg must be in [0, 360), got " +
                                std::to_string(cut_angle_deg));
  }
  if (!(silence_timeout_ms > 0.0)) {
    throw std::invalid_argument("assembler: silence_timeout_ms must be > 0, got " +
                                std::to_string(silence_timeout_ms));
  }
  if (!(max_gap_fill_deg >= 0.0 && max_gap_fill_deg < 360.0)) {
    throw std::invalid_argument("assembler: max_gap_fill_deg must be in [0, 360), got " +
                                std::to_string(max_gap_fill_deg));
  }
  if (capacity_columns < 2 * kMaxColumnsPerPacket) {
    throw std::invalid_argument("assembler: capacity_columns must be >= 48, got " +
                                std::to_string(capacity_columns));
  }
}

RotationAssembler::RotationAssembler(const AssemblerConfig& config)
    : config_((config.validate(), config)),
      current_(config.capacity_columns),
      ready_{Frame(config.capacity_columns), Frame(config.capacity_columns)} {
  laser_of_ring_[static_cast<std::size_t>(Model::vlp16)] = default_laser_of_ring();
  laser_of_ring_[static_cast<std::size_t>(Model::hires)] = default_laser_of_ring();
}

void RotationAssembler::set_laser_of_ring(Model model,
                                          const std::array<std::uint8_t, kLasers>& order) {
  laser_of_ring_[static_cast<std::size_t>(model)] = order;
}

bool RotationAssembler::push(const DecodedPacket& packet, Frame& out,
                             std::int64_t steady_receive_ns) {
  if (packet.column_count <= 0 || packet.column_count > kMaxColumnsPerPacket) {
    note_skipped_packet();
    return deliver(out);
  }
  const std::int64_t steady = steady_receive_ns >= 0 ? steady_receive_ns : packet.receive_ns;
  const auto silence_ns = static_cast<std::int64_t>(config_.silence_timeout_ms * 1e6);
  if (have_packet_ && packet.time_rebase_ns != 0) rebase_time(packet.time_rebase_ns);
  if (have_packet_) {
    const std::int64_t period = packet_period_ns(packet.mode);
    const std::int64_t delta = packet.time_ns - last_packet_time_ns_;
    if (packet.mode != mode_ || packet.model != model_ || delta < -silence_ns) {
      ++counters_.stream_changes;
      finish_frame(false, FrameEnd::stream_change);
      restart_stream();
    } else if (delta == 0) {
      ++counters_.duplicate_packets;
      ++current_.meta.packets_skipped;
      return deliver(out);
    } else if (delta < 0) {
      ++counters_.reordered_packets;
      ++current_.meta.packets_skipped;
      return deliver(out);
    } else if (2 * delta < period || (last_seen_time_ns_ < packet.time_ns &&
                                      2 * (packet.time_ns - last_seen_time_ns_) < period)) {
      // Closer than half a period to the newest packet seen, even a skipped one: not the
      // VLP-16's timing (an HDL-32E sends every 553 us) or a corrupt stamp.
      last_seen_time_ns_ = packet.time_ns;
      ++counters_.off_grid_packets;
      ++current_.meta.packets_skipped;
      return deliver(out);
    } else if (delta > silence_ns) {
      ++counters_.silences;
      finish_frame(false, FrameEnd::silence);
      restart_stream();
    } else if (2 * delta > 3 * period) {
      steady_ns_ = steady;  // a frame ended by the gap completes with this packet
      handle_gap(packet, delta);
    }
  }
  steady_ns_ = steady;
  mode_ = packet.mode;
  model_ = packet.model;
  time_source_ = packet.time_source;
  packet_in_frame_ = false;

  // Rotation rate over the packet (the decoder's per-laser azimuths already interpolate).
  const auto n = static_cast<std::size_t>(packet.column_count);
  const auto& azimuth = packet.azimuth_deg[0];  // laser 0 of each column
  const auto& time = packet.column_time_ns;
  if (n >= 2 && time[n - 1] > time[0]) {
    rate_deg_per_ns_ =
        forward_deg(azimuth[0], azimuth[n - 1]) / static_cast<double>(time[n - 1] - time[0]);
  }
  for (std::size_t c = 0; c < n; ++c) {
    add_column(ColumnSource{&packet, time[c], azimuth[c], packet.packet_index,
                            static_cast<std::uint8_t>(c), false});
  }
  write_pending_run();
  have_packet_ = true;
  last_packet_time_ns_ = packet.time_ns;
  last_seen_time_ns_ = packet.time_ns;
  ++counters_.packets_used;
  return deliver(out);
}

// Fills a timestamp gap with invalid columns on the firing grid, or ends the frame when the
// gap is too large to fill. The azimuth advance across the gap is the wrapped difference plus
// the whole turns the measured rate says fit in the gap.
void RotationAssembler::handle_gap(const DecodedPacket& packet, std::int64_t delta_ns) {
  const std::int64_t period = packet_period_ns(packet.mode);
  const auto lost_packets = static_cast<std::uint64_t>(std::llround(static_cast<double>(delta_ns) /
                                                                    static_cast<double>(period))) -
                            1;
  const std::int64_t span_ns = packet.time_ns - last_column_time_ns_;
  const std::int64_t missing = std::llround(static_cast<double>(span_ns) / kSequencePeriodNs) - 1;
  const double end_az = packet.azimuth_deg[0][0];
  double advance = forward_deg(last_column_az_deg_, end_az);
  if (rate_deg_per_ns_ > 0.0) {
    const double expected = rate_deg_per_ns_ * static_cast<double>(span_ns);
    advance += 360.0 * std::round((expected - advance) / 360.0);
  }
  // FOV sector: the same silent azimuths as the previous gap, within ~1.5 packets.
  const double tolerance = std::max(2.0, 1.5 * rate_deg_per_ns_ * static_cast<double>(period));
  const bool fov = have_gap_ && advance < kMaxFovGapDeg &&
                   driver_detail::distance_deg(last_column_az_deg_, gap_start_deg_) <= tolerance &&
                   driver_detail::distance_deg(end_az, gap_end_deg_) <= tolerance;
  have_gap_ = true;
  gap_start_deg_ = last_column_az_deg_;
  gap_end_deg_ = end_az;
  if (!fov) counters_.packets_lost += lost_packets;

  if (missing <= 0) return;
  if ((!fov && advance > config_.max_gap_fill_deg) || advance >= 360.0 ||
      missing >= config_.capacity_columns) {
    ++counters_.large_gaps;
    current_.meta.packets_lost += static_cast<std::uint32_t>(lost_packets);
    finish_frame(false, FrameEnd::gap);
    restart_stream();  // keeps the gap's azimuths to recognise a FOV sector next rotation
    return;
  }
  if (!fov) current_.meta.packets_lost += static_cast<std::uint32_t>(lost_packets);
  const double start_az = last_column_az_deg_;
  const std::int64_t start_ns = last_column_time_ns_;
  for (std::int64_t k = 1; k <= missing; ++k) {
    const double f = static_cast<double>(k) / static_cast<double>(missing + 1);
    add_column(ColumnSource{nullptr, start_ns + k * kSequencePeriodNs,
                            wrap_deg(start_az + advance * f), kNoPacketIndex, kNoColumnInPacket,
                            fov});
  }
}

// The hour reference changed under a continuous stream: earlier times move with it, so the
// frame in progress continues on the new clock (time offsets are relative: unchanged).
void RotationAssembler::rebase_time(std::int64_t shift_ns) {
  ++counters_.clock_rebases;
  last_packet_time_ns_ += shift_ns;
  last_seen_time_ns_ += shift_ns;
  last_column_time_ns_ += shift_ns;
  current_.meta.first_time_ns += shift_ns;
  for (int c = 0; c < current_.columns(); ++c) {
    current_.column_time_ns[static_cast<std::size_t>(c)] += shift_ns;
  }
}

void RotationAssembler::add_column(const ColumnSource& source) {
  if (!have_column_) {
    begin_frame(source, false);
  } else {
    double advance = forward_deg(last_column_az_deg_, source.azimuth_deg);
    if (advance > 360.0 - kJitterDeg) advance = 0.0;  // encoder jitter, not a turn
    if (advance > kMaxColumnStepDeg) {
      // An azimuth jump between consecutive firings (edited capture, corrupt block): keep
      // the columns, but no cut is judged across it and the frame is not a clean rotation.
      ++counters_.azimuth_jumps;
      frame_at_cut_ = false;
    } else if (forward_deg(config_.cut_angle_deg, source.azimuth_deg) < advance) {
      // The seam: the cut lies in (previous, this] going forward.
      finish_frame(frame_at_cut_, FrameEnd::cut);
      begin_frame(source, true);
    } else {
      frame_advance_deg_ += advance;
    }
  }
  int col = current_.append_column_for_overwrite();
  if (col < 0) {
    ++counters_.capacity_overflows;
    finish_frame(false, FrameEnd::capacity);
    begin_frame(source, false);
    col = current_.append_column_for_overwrite();
  }
  write_column_header(col, source);
  if (source.packet != nullptr) {
    extend_pending_run(col, source);
    if (!packet_in_frame_) {
      packet_in_frame_ = true;
      ++current_.meta.packets_used;
    }
  } else {
    write_empty_cells(col, source);
    if (source.outside_fov) {
      ++current_.meta.columns_outside_fov;
      ++counters_.columns_outside_fov;
    } else {
      ++current_.meta.columns_lost;
      ++counters_.columns_lost;
    }
  }
  have_column_ = true;
  last_column_time_ns_ = source.time_ns;
  last_column_az_deg_ = source.azimuth_deg;
}

void RotationAssembler::begin_frame(const ColumnSource& source, bool at_cut) {
  // current_ is empty here (finish_frame() swapped it out or it never held a column).
  current_.meta.first_time_ns = source.time_ns;
  current_.meta.mode = mode_;
  current_.meta.model = model_;
  const auto& order = laser_of_ring_[static_cast<std::size_t>(model_)];
  for (std::size_t r = 0; r < order.size(); ++r) current_.laser_of_ring[r] = order[r];
  frame_at_cut_ = at_cut;
  frame_advance_deg_ = 0.0;
  packet_in_frame_ = false;
}

void RotationAssembler::write_column_header(int col, const ColumnSource& source) {
  const auto c = static_cast<std::size_t>(col);
  current_.column_azimuth_deg[c] = static_cast<float>(source.azimuth_deg);
  current_.column_time_ns[c] = source.time_ns;
  current_.column_valid[c] = source.packet != nullptr ? 1 : 0;
  current_.column_packet_index[c] = source.packet_index;
  current_.column_in_packet[c] = source.in_packet;
}

// Consecutive columns of one packet that land in consecutive frame columns are copied
// together: a ring's cells are contiguous in both (DecodedPacket rows, Frame rows).
void RotationAssembler::extend_pending_run(int col, const ColumnSource& source) {
  PendingRun& run = pending_;
  if (run.count > 0 && run.packet == source.packet && run.first_col + run.count == col &&
      run.first_in_packet + run.count == source.in_packet) {
    ++run.count;
    return;
  }
  write_pending_run();
  run = PendingRun{source.packet, source.in_packet, col, 1};
}

void RotationAssembler::write_pending_run() {
  if (pending_.count == 0) return;
  driver_detail::copy_packet_run(*pending_.packet, pending_.first_in_packet, pending_.count,
                                 pending_.first_col, current_);
  pending_.count = 0;
}

void RotationAssembler::write_empty_cells(int col, const ColumnSource& source) {
  const double base_us = static_cast<double>(source.time_ns - current_.meta.first_time_ns) * 1e-3;
  for (int ring = 0; ring < kLasers; ++ring) {
    const std::size_t laser = current_.laser_of_ring[ring];
    const std::size_t i = current_.index(ring, col);
    const auto offset_us =
        static_cast<float>(base_us + static_cast<double>(laser) * (kFiringIntervalNs * 1e-3));
    for (ReturnLayer& dst : current_.layer) {
      dst.range_m[i] = dst.x_m[i] = dst.y_m[i] = dst.z_m[i] = 0.f;
      dst.azimuth_deg[i] = static_cast<float>(source.azimuth_deg);
      dst.time_offset_us[i] = offset_us;
      dst.intensity[i] = 0;
      dst.valid[i] = 0;
    }
    current_.same_echo[i] = 0;
  }
}

// Moves the frame in progress (if it holds columns) to the ready FIFO.
void RotationAssembler::finish_frame(bool complete, FrameEnd end) {
  write_pending_run();
  if (current_.columns() == 0) return;
  FrameMeta& meta = current_.meta;
  const auto last = static_cast<std::size_t>(current_.columns() - 1);
  meta.last_time_ns = current_.column_time_ns[last] + (kLasers - 1) * kFiringIntervalNs;
  const std::int64_t span_ns = current_.column_time_ns[last] - meta.first_time_ns;
  meta.rpm = span_ns > 0 ? rpm_from_rate(frame_advance_deg_ / static_cast<double>(span_ns))
                         : rpm_from_rate(rate_deg_per_ns_);
  meta.complete = complete;
  meta.end = end;
  meta.sequence = next_sequence_++;
  meta.completed_receive_ns = steady_ns_;
  meta.time_source = time_source_;
  ++counters_.frames;
  if (!complete) ++counters_.incomplete_frames;

  if (ready_count_ == static_cast<int>(ready_.size())) {  // caller did not pop(): drop oldest
    ++counters_.frames_dropped;
    ready_head_ = (ready_head_ + 1) % static_cast<int>(ready_.size());
    --ready_count_;
  }
  const int slot = (ready_head_ + ready_count_) % static_cast<int>(ready_.size());
  std::swap(current_, ready_[static_cast<std::size_t>(slot)]);
  ++ready_count_;
  if (current_.capacity() != config_.capacity_columns) {
    current_.reserve(config_.capacity_columns);  // only if a caller passed a smaller frame
  }
  current_.clear();
  packet_in_frame_ = false;
}

void RotationAssembler::restart_stream() {
  have_packet_ = false;
  have_column_ = false;
}

bool RotationAssembler::deliver(Frame& out) {
  if (ready_count_ == 0) return false;
  std::swap(out, ready_[static_cast<std::size_t>(ready_head_)]);
  ready_head_ = (ready_head_ + 1) % static_cast<int>(ready_.size());
  --ready_count_;
  return true;
}

bool RotationAssembler::pop(Frame& out) { return deliver(out); }

bool RotationAssembler::flush(Frame& out) {
  if (ready_count_ == 0) {
    finish_frame(false, FrameEnd::end_of_input);
    restart_stream();
  }
  return deliver(out);
}

bool RotationAssembler::expire(std::int64_t steady_now_ns, Frame& out) {
  const auto silence_ns = static_cast<std::int64_t>(config_.silence_timeout_ms * 1e6);
  if (current_.columns() > 0 && steady_now_ns - steady_ns_ > silence_ns) {
    ++counters_.silences;
    finish_frame(false, FrameEnd::silence);
    restart_stream();
  }
  return deliver(out);
}

void RotationAssembler::discard_frame() {
  pending_.count = 0;
  const std::uint32_t used = current_.meta.packets_used;
  counters_.packets_used -= std::min<std::uint64_t>(counters_.packets_used, used);
  counters_.discarded_packets += used;
  const std::uint32_t skipped = current_.meta.packets_skipped;
  current_.clear();
  current_.meta.packets_skipped = skipped + used;
  restart_stream();
}

void RotationAssembler::note_skipped_packet() {
  ++counters_.skipped_upstream;
  ++current_.meta.packets_skipped;
}

}  // namespace vlpground
