#include "cli/capture_summary.hpp"

#include <algorithm>
#include <cstdio>

#include "vlpground/driver/sensor_model.hpp"

namespace vlpground::cli {
namespace {

const char* gprmc_state(bool seen, bool valid) {
  return seen ? (valid ? "valid" : "void") : "absent";
}

template <class T>
nlohmann::json or_null(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json();
}

template <class Enum>
nlohmann::json name_or_null(const std::optional<Enum>& v) {
  return v ? nlohmann::json(std::string(to_string(*v))) : nlohmann::json();
}

}  // namespace

void CaptureSummary::add_frame(const FrameMeta& meta) {
  if (frames_ == 0) first_ns_ = meta.first_time_ns;
  last_ns_ = meta.last_time_ns;
  ++frames_;
  if (meta.complete) {
    ++complete_frames_;
    rpm_sum_ += meta.rpm;
  } else if (meta.rpm > 0) {
    partial_rpm_sum_ += meta.rpm;  // short captures: no complete rotation
    ++partial_rpm_frames_;
  }
  model_ = meta.model;
  mode_ = meta.mode;
  time_source_ = meta.time_source;
  if (meta.calibration) calibration_ = meta.calibration->source;
}

void CaptureSummary::add_position(const PositionPacket& p) {
  ++positions_;
  pps_ = p.pps;
  if (!p.gprmc.parsed) return;
  gprmc_seen_ = true;
  gprmc_valid_ = p.gprmc.valid;
  char t[64];
  std::snprintf(t, sizeof t, "%04d-%02d-%02dT%02d:%02d:%06.3fZ", p.gprmc.year, p.gprmc.month,
                p.gprmc.day, p.gprmc.hour, p.gprmc.minute, p.gprmc.second);
  gprmc_time_ = t;
}

void CaptureSummary::add_warning(const std::string& message) {
  if (warnings_.size() >= kMaxWarnings ||
      std::find(warnings_.begin(), warnings_.end(), message) != warnings_.end()) {
    return;
  }
  warnings_.push_back(message);
}

void CaptureSummary::set_mode_if_unknown(std::optional<ReturnMode> mode) {
  if (!mode_) mode_ = mode;
}

std::optional<double> CaptureSummary::rpm() const {
  if (complete_frames_ > 0) return rpm_sum_ / static_cast<double>(complete_frames_);
  if (partial_rpm_frames_ > 0) return partial_rpm_sum_ / static_cast<double>(partial_rpm_frames_);
  return std::nullopt;
}

double CaptureSummary::duration_s() const {
  return static_cast<double>(last_ns_ - first_ns_) * 1e-9;
}

std::string CaptureSummary::gps_line() const {
  std::string line = std::string("PPS ") + pps_name(pps_) + ", GPRMC " +
                     gprmc_state(gprmc_seen_, gprmc_valid_);
  if (!gprmc_time_.empty()) line += ", " + gprmc_time_;
  return line;
}

void CaptureSummary::add_json_fields(nlohmann::json& j) const {
  j["model"] = name_or_null(model_);
  j["return_mode"] = name_or_null(mode_);
  j["rpm"] = or_null(rpm());
  j["time_source"] = name_or_null(time_source_);
  j["calibration"] = or_null(calibration_);
  j["duration_s"] = duration_s();
  j["gps"] = {{"pps", pps_name(pps_)},
              {"gprmc", gprmc_state(gprmc_seen_, gprmc_valid_)},
              {"time", gprmc_time_.empty() ? nlohmann::json() : nlohmann::json(gprmc_time_)}};
  j["warnings"] = warnings_;
}

nlohmann::json packets_json(const CaptureCounters& c) {
  const auto& src = c.source;
  const auto& dec = c.decoder;
  const auto& as = c.assembler;
  return {{"records", src.records},
          {"data", src.data_packets},
          {"position", src.position_packets},
          {"skipped", src.skipped()},
          {"truncated", src.truncated},
          {"kernel_drops", src.kernel_drops},
          {"decoded", dec.decoded},
          {"malformed", dec.wrong_size + dec.bad_flag + dec.bad_azimuth + dec.unknown_mode},
          {"product_mismatch", dec.product_mismatch},
          {"lost", as.packets_lost},
          {"duplicate", as.duplicate_packets},
          {"reordered", as.reordered_packets}};
}

nlohmann::json frames_json(std::uint64_t delivered, std::uint64_t incomplete) {
  return {{"delivered", delivered},
          {"complete", delivered - std::min(incomplete, delivered)},
          {"incomplete", incomplete}};
}

}  // namespace vlpground::cli
