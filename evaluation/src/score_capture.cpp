// Capture-level scoring: pcap -> CaptureReader -> GroundDetector -> FrameScorer.
#include <chrono>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/evaluation/evaluation.hpp"

namespace vlpground::eval {

CaptureScore score_capture(const std::filesystem::path& pcap_path,
                           const std::filesystem::path& labels_path, const DetectorConfig& detector,
                           double radius_m) {
  CaptureScoreOptions options;
  options.score.radius_m = radius_m;
  return score_capture(pcap_path, labels_path, detector, options);
}

CaptureScore score_capture(const std::filesystem::path& pcap_path,
                           const std::filesystem::path& labels_path, const DetectorConfig& detector,
                           const CaptureScoreOptions& options) {
  return score_capture(pcap_path, labels_path, std::span<const DetectorConfig>(&detector, 1),
                       options)
      .front();
}

std::vector<CaptureScore> score_capture(const std::filesystem::path& pcap_path,
                                        const std::filesystem::path& labels_path,
                                        std::span<const DetectorConfig> detectors,
                                        const CaptureScoreOptions& options) {
  if (options.max_frames < 0) {
    throw std::invalid_argument("CaptureScoreOptions: max_frames must be >= 0 (0 = all)");
  }
  if (detectors.empty()) throw std::invalid_argument("score_capture: no detector configuration");
  const GroundTruth truth = GroundTruth::load_with_heights(labels_path);
  FrameScorer scorer(options.score);
  std::vector<GroundDetector> ground;
  std::vector<CaptureScore> out(detectors.size());
  for (std::size_t k = 0; k < detectors.size(); ++k) {
    ground.emplace_back(detectors[k]);
    out[k].capture = pcap_path.stem().string();
    out[k].method = std::string(to_string(detectors[k].method));
  }

  PcapSourceConfig source;
  source.path = pcap_path.string();
  CaptureReader reader(open_pcap_source(source));
  Frame frame;
  GroundResult result;
  result.reserve(frame.capacity());
  int scored = 0;
  while (options.max_frames == 0 || scored < options.max_frames) {
    const ReadStatus status = reader.next(frame);
    if (status == ReadStatus::timeout) continue;  // replay does not time out; be tolerant
    if (status != ReadStatus::frame) break;
    if (options.skip_incomplete && !frame.meta.complete) continue;
    for (std::size_t k = 0; k < detectors.size(); ++k) {
      const auto start = std::chrono::steady_clock::now();
      ground[k].detect(frame, result);
      out[k].detect_ms_total +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      const Score frame_score = scorer.score(frame, result, truth);
      out[k].score += frame_score;
      if (options.on_frame) options.on_frame(k, frame, result, frame_score);
    }
    ++scored;
  }
  return out;
}

Extrinsics load_sim_extrinsics(const std::filesystem::path& json_path) {
  std::ifstream in(json_path);
  if (!in) throw std::runtime_error("cannot open '" + json_path.string() + "'");
  Extrinsics e;
  try {
    const auto doc = nlohmann::json::parse(in);
    e.z_m = doc.value("sensor_height_m", 0.0);
    if (doc.contains("mount_roll_pitch_deg")) {
      const auto& rp = doc.at("mount_roll_pitch_deg");
      e.roll_deg = rp.at(0).get<double>();
      e.pitch_deg = rp.at(1).get<double>();
    }
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error("'" + json_path.string() + "': " + ex.what());
  }
  return e;
}

void check_labels_match(const SourceCounters& capture, const std::filesystem::path& labels_path,
                        const std::filesystem::path& sim_json) {
  std::ifstream labels(labels_path, std::ios::binary);  // any file, /dev/null included
  labels.ignore(std::numeric_limits<std::streamsize>::max());
  const auto bytes = static_cast<std::uint64_t>(labels.gcount());
  const std::uint64_t labelled = bytes / kSlotsPerPacket;
  if (bytes % kSlotsPerPacket != 0 || labelled != capture.data_packets) {
    throw std::runtime_error("labels file " + labels_path.string() + ": labels cover " +
                             std::to_string(labelled) + " packets (" + std::to_string(bytes) +
                             " bytes), the capture has " + std::to_string(capture.data_packets));
  }
  if (!std::filesystem::exists(sim_json)) return;
  std::ifstream in(sim_json);
  const auto j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object() || !j.contains("packets") || !j["packets"].is_number_unsigned()) return;
  // The simulator counts data packets; older captures counted position packets too.
  const auto described = j["packets"].get<std::uint64_t>();
  if (described != capture.data_packets &&
      described != capture.data_packets + capture.position_packets) {
    throw std::runtime_error(sim_json.string() + " describes " + std::to_string(described) +
                             " packets, the capture has " + std::to_string(capture.data_packets));
  }
}

}  // namespace vlpground::eval
