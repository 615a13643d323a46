// What `info --json` and the `replay`/`live` JSON summaries both say about a capture, built in
// one place so that each field has one JSON type and one meaning everywhere (the schema is in
// docs/cli-json.md): model, return mode, rpm, time source, calibration, duration, frames,
// packets, GPS/PPS and warnings.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::cli {

/// Facts gathered from the frames and position packets of a run. A plain value: callers on
/// several threads guard it themselves.
class CaptureSummary {
 public:
  void add_frame(const FrameMeta& meta);
  void add_position(const PositionPacket& packet);
  /// Distinct messages are kept (at most kMaxWarnings); repeats are not.
  void add_warning(const std::string& message);
  /// When no frame was decoded (not a VLP-16 capture), the return-mode byte seen.
  void set_mode_if_unknown(std::optional<ReturnMode> mode);

  /// Mean rpm of the complete rotations; of the partial ones when there is none.
  [[nodiscard]] std::optional<double> rpm() const;
  /// Sensor time from the first firing of the first frame to the last of the last frame.
  [[nodiscard]] double duration_s() const;
  [[nodiscard]] std::uint64_t frames() const { return frames_; }
  [[nodiscard]] std::uint64_t complete_frames() const { return complete_frames_; }
  [[nodiscard]] std::optional<ReturnMode> return_mode() const { return mode_; }
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }
  [[nodiscard]] bool has_position() const { return positions_ > 0; }
  /// "PPS locked, GPRMC valid, 2023-11-14T22:00:01.000Z" for the tables.
  [[nodiscard]] std::string gps_line() const;

  /// The shared fields (model, return_mode, rpm, time_source, calibration, duration_s, gps,
  /// warnings) added to `j`.
  void add_json_fields(nlohmann::json& j) const;

  static constexpr std::size_t kMaxWarnings = 32;

 private:
  std::uint64_t frames_ = 0, complete_frames_ = 0, partial_rpm_frames_ = 0;
  double rpm_sum_ = 0, partial_rpm_sum_ = 0;
  std::int64_t first_ns_ = 0, last_ns_ = 0;
  std::optional<Model> model_;
  std::optional<ReturnMode> mode_;
  std::optional<TimeSource> time_source_;
  std::optional<std::string> calibration_;
  std::uint64_t positions_ = 0;
  PpsStatus pps_ = PpsStatus::absent;
  bool gprmc_seen_ = false, gprmc_valid_ = false;
  std::string gprmc_time_;  // ISO 8601 UTC of the latest parsed $GPRMC
  std::vector<std::string> warnings_;
};

/// The packet counters of a capture, one key set for every command.
nlohmann::json packets_json(const CaptureCounters& c);

/// {"delivered", "complete", "incomplete"}: frames handed out and how many were full rotations.
nlohmann::json frames_json(std::uint64_t delivered, std::uint64_t incomplete);

}  // namespace vlpground::cli
