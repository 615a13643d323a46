#include "vlpground/driver/capture_reader.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace vlpground {
namespace {

constexpr std::int64_t kHourNs = 3'600'000'000'000;

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The UTC top of the hour the sensor's stamps count from: the fix time minus the packet's
// microseconds past the hour, rounded to the nearest hour (they differ by the GPS latency).
std::int64_t top_of_hour_ns(const PositionPacket& p) {
  const std::int64_t approx = p.gprmc.utc_ns() - std::int64_t{p.stamp_us_past_hour} * 1000;
  const std::int64_t floor_hours =
      approx >= 0 ? approx / kHourNs : (approx - kHourNs + 1) / kHourNs;
  const std::int64_t rest = approx - floor_hours * kHourNs;
  return (floor_hours + (2 * rest >= kHourNs ? 1 : 0)) * kHourNs;
}

}  // namespace

struct CaptureReader::Impl {
  Impl(std::unique_ptr<PacketSource> s, const DecoderConfig& d, const AssemblerConfig& a)
      : source(std::move(s)), decoder_config(d), decoder(d), assembler(a) {
    for (Model m : {Model::vlp16, Model::hires}) {
      assembler.set_laser_of_ring(m, decoder.sensor_model(m).laser_of_ring);
    }
  }

  std::unique_ptr<PacketSource> source;
  DecoderConfig decoder_config;
  PacketDecoder decoder;
  RotationAssembler assembler;
  DecodedPacket decoded;
  PositionPacket position;
  PacketView view;
  std::function<void(const PositionPacket&)> position_callback;
  std::function<void(std::error_code, const std::string&)> warning_callback;
  std::vector<std::string> warned;  // distinct warnings already forwarded
  std::atomic<bool> stop{false};
  bool ended = false;
  std::uint64_t position_packets_parsed = 0;
  bool warned_timing = false;

  void warn_once(std::error_code code, const std::string& text) {
    if (text.empty() || std::find(warned.begin(), warned.end(), text) != warned.end()) return;
    warned.push_back(text);
    if (warning_callback) warning_callback(code, text);
  }

  void check_warnings() {
    const std::string& w = decoder.last_warning();
    if (!w.empty() && (warned.empty() || warned.back() != w)) warn_once(decoder.last_warning_code(), w);
    if (!warned_timing && assembler.counters().off_grid_packets >= 8 &&
        assembler.counters().off_grid_packets > assembler.counters().packets_used) {
      warned_timing = true;
      warn_once(
          ErrorCode::not_vlp16_timing,
          "data packets arrive closer together than a VLP-16's packet period (1327.104 us, "
          "663.552 us dual): this does not look like a VLP-16 stream (HDL-32E?); packets skipped");
    }
  }

  void handle_position() {
    if (!parse_position_packet(view.bytes, view.receive_ns, position)) return;
    ++position_packets_parsed;
    decoder.note_gps_status(position);
    if (decoder_config.use_gps_hour && position.pps == PpsStatus::locked && position.gprmc.parsed &&
        position.gprmc.valid) {
      decoder.set_gps_hour_reference(top_of_hour_ns(position));
    }
    if (position_callback) position_callback(position);
  }

  // True when `out` received a frame.
  bool handle_data(Frame& out) {
    const DecodeStatus status = decoder.decode(view.bytes, view.receive_ns, decoded, view.stamp_offset_ns);
    if (status != DecodeStatus::ok) {
      // The first packets of another sensor family decode before the timing verdict: drop
      // the frame they started.
      if (status == DecodeStatus::not_vlp16 && decoder.counters().not_vlp16 == 1) {
        assembler.discard_frame();
      }
      assembler.note_skipped_packet();
      check_warnings();
      return false;
    }
    const bool got = assembler.push(decoded, out, view.steady_receive_ns);
    check_warnings();
    return got;
  }

  ReadStatus next(Frame& out, int timeout_ms) {
    const ReadStatus status = next_frame(out, timeout_ms);
    if (status == ReadStatus::frame) out.meta.calibration = decoder.calibration(out.meta.model);
    return status;
  }

  ReadStatus next_frame(Frame& out, int timeout_ms) {
    if (assembler.pop(out)) return ReadStatus::frame;
    if (ended) return assembler.flush(out) ? ReadStatus::frame : ReadStatus::end_of_input;
    while (!stop.load(std::memory_order_relaxed)) {
      switch (source->next(view, timeout_ms)) {
        case SourceStatus::packet:
          if (view.kind == PacketKind::position) {
            handle_position();
          } else if (handle_data(out)) {
            return ReadStatus::frame;
          }
          break;
        case SourceStatus::timeout:
          return assembler.expire(steady_now_ns(), out) ? ReadStatus::frame : ReadStatus::timeout;
        case SourceStatus::end_of_file:
          ended = true;
          return assembler.flush(out) ? ReadStatus::frame : ReadStatus::end_of_input;
        case SourceStatus::stopped:
          return ReadStatus::stopped;
      }
    }
    return ReadStatus::stopped;
  }
};

CaptureReader::CaptureReader(std::unique_ptr<PacketSource> source, const DecoderConfig& decoder,
                             const AssemblerConfig& assembler)
    : impl_(std::make_unique<Impl>(std::move(source), decoder, assembler)) {}

CaptureReader::~CaptureReader() = default;

ReadStatus CaptureReader::next(Frame& out, int timeout_ms) { return impl_->next(out, timeout_ms); }

void CaptureReader::request_stop() {
  impl_->stop.store(true, std::memory_order_relaxed);
  impl_->source->request_stop();
}

void CaptureReader::on_position(std::function<void(const PositionPacket&)> callback) {
  impl_->position_callback = std::move(callback);
}

void CaptureReader::on_warning(
    std::function<void(std::error_code, const std::string&)> callback) {
  impl_->warning_callback = std::move(callback);
}

CaptureCounters CaptureReader::counters() const {
  return CaptureCounters{impl_->source->counters(), impl_->decoder.counters(),
                         impl_->assembler.counters(), impl_->position_packets_parsed};
}

const PacketSource& CaptureReader::source() const { return *impl_->source; }

}  // namespace vlpground
