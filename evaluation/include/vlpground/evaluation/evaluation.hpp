// Accuracy evaluation of ground detection against per-return-slot ground truth (the
// simulator's `.labels` files, format in ../shared/data/sim/README.md, and, when present, the
// `.heights` beside them: each echo's exact height above the terrain, README "Data formats").
//
// Scoring rule (README + brief): returns within `radius_m` horizontally of the sensor whose
// truth is ground (1) or obstacle (2); ground is the positive class. Ambiguous (3) returns are
// left out. In dual mode both layers are scored, except a last-return cell that holds the same
// echo as the strongest one (it would count the same return twice).
//
// Thread-safety: GroundTruth is immutable after construction (share freely); a FrameScorer
// keeps reusable buffers, use one per thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::eval {

/// Values of a ground-truth byte.
enum class TruthLabel : std::uint8_t { none = 0, ground = 1, obstacle = 2, ambiguous = 3 };

inline constexpr int kSlotsPerPacket = 384;  // 12 blocks x 32 channels

/// X.labels -> X.heights: where the simulator writes each slot's height above the terrain
/// beside its labels. The one place that rule lives; every front-end goes through
/// GroundTruth::load_with_heights().
std::filesystem::path heights_path_beside(const std::filesystem::path& labels_path);

/// Ground truth of one capture: one byte per return slot of every data packet and, optionally,
/// each slot's exact height above the terrain (int16 centimetres, same slot order; 0 for
/// ground and empty slots).
class GroundTruth {
 public:
  GroundTruth() = default;
  /// Throws std::invalid_argument when the size is not a multiple of 384 or a byte is > 3.
  explicit GroundTruth(std::vector<std::uint8_t> bytes);
  /// Labels with heights: also throws std::invalid_argument when `heights_cm` does not hold
  /// one value per label slot.
  GroundTruth(std::vector<std::uint8_t> bytes, std::vector<std::int16_t> heights_cm);
  /// Throws std::runtime_error naming the file when it is missing or unreadable, and
  /// std::invalid_argument (with the file name) when its content is malformed.
  static GroundTruth load(const std::filesystem::path& path);
  /// Labels and the heights file `heights_path` (2 bytes per label slot, little-endian int16
  /// centimetres). Throws as load(), naming the heights file when it does not match.
  static GroundTruth load(const std::filesystem::path& labels_path,
                          const std::filesystem::path& heights_path);
  /// What every front-end loads: the labels, with heights_path_beside(labels_path) when that
  /// file exists (simulator captures), else labels only (the terrain is then estimated).
  static GroundTruth load_with_heights(const std::filesystem::path& labels_path);

  [[nodiscard]] std::uint64_t packets() const { return bytes_.size() / kSlotsPerPacket; }
  /// Truth of slot `block * 32 + channel` of data packet `packet`; `none` past the end.
  [[nodiscard]] TruthLabel at(std::uint64_t packet, int slot) const;
  /// Whether exact heights above the terrain came with the labels.
  [[nodiscard]] bool has_heights() const { return !heights_cm_.empty(); }
  /// Height of the slot's echo above the terrain (m); empty without heights or past the end.
  [[nodiscard]] std::optional<float> height_above_terrain_m(std::uint64_t packet, int slot) const;

 private:
  std::vector<std::uint8_t> bytes_;
  std::vector<std::int16_t> heights_cm_;  // empty, or one per label byte
};

/// Wire position of a frame cell: slot = block * 32 + channel within its data packet.
struct SlotRef {
  std::uint64_t packet = 0;
  int block = 0;
  int channel = 0;
  [[nodiscard]] int slot() const { return block * 32 + channel; }
};

/// Where cell (ring, col) of `layer` came from. Single return: block = j/2,
/// channel = (j%2)*16 + laser, with j = column_in_packet. Dual: pair p = j/2; the last
/// return (layer 1) is in block 2p, the strongest (layer 0) in block 2p+1.
SlotRef slot_of_cell(const Frame& frame, int ring, int col, int layer);

/// Binary confusion counts, ground positive.
struct Confusion {
  std::uint64_t tp = 0, fp = 0, fn = 0, tn = 0;
  [[nodiscard]] std::uint64_t total() const { return tp + fp + fn + tn; }
  [[nodiscard]] double precision() const;  // 0 when nothing was predicted ground
  [[nodiscard]] double recall() const;     // 0 when there is no truth ground
  [[nodiscard]] double f1() const;
  Confusion& operator+=(const Confusion& o);
};

struct ScoreConfig {
  double radius_m = 40.0;         // horizontal distance from the sensor
  double band_split_m = 20.0;     // range bands [0, split) and [split, radius)
  double high_obstacle_m = 0.5;   // "high" obstacle: this far above the terrain
  double terrain_radius_m = 2.5;  // truth-ground neighbours used to estimate the terrain
  double sector_deg = 5.0;        // fallback: angular sector searched for terrain
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

/// How the terrain under the scored truth obstacles was known (Score::terrain_source).
enum class TerrainSource : std::uint8_t {
  none,       // no truth obstacle was scored
  exact,      // every one by the capture's exact heights (STEM.heights)
  estimated,  // every one by the estimate from the truth-ground returns
  mixed,      // some each way (a sum over captures with and without heights)
};
/// "none", "exact", "estimated", "mixed".
std::string_view to_string(TerrainSource source);

struct Score {
  Confusion all;
  Confusion near_band, far_band;  // [0, band_split_m), [band_split_m, radius_m)
  // Truth obstacles more than high_obstacle_m above the terrain, and how many of them were
  // labelled ground. The height above the terrain is the ground truth's exact one when it has
  // heights; otherwise estimated: terrain height under an obstacle return = median z of the
  // truth-ground returns within terrain_radius_m horizontally (same frame); when there are
  // none, the z of the truth-ground return of the same angular sector nearest in range.
  std::uint64_t high_obstacles = 0;
  std::uint64_t high_obstacles_as_ground = 0;
  std::uint64_t obstacles_exact_terrain = 0;      // judged by their exact height
  std::uint64_t obstacles_estimated_terrain = 0;  // judged against the estimated terrain
  std::uint64_t obstacles_without_terrain = 0;    // no heights, no truth ground in the sector
  // Alignment checks: a cell with a return whose slot says "none", and the reverse.
  std::uint64_t returns_without_truth = 0;
  std::uint64_t truth_without_return = 0;
  std::uint64_t ambiguous_skipped = 0;
  std::uint64_t frames = 0;

  [[nodiscard]] double high_obstacle_as_ground_rate() const;  // 0 when there are none
  [[nodiscard]] TerrainSource terrain_source() const;
  Score& operator+=(const Score& o);
};

/// Scores one labelled frame. Keeps its buffers between calls (no allocation once warm).
class FrameScorer {
 public:
  explicit FrameScorer(const ScoreConfig& config = {});
  /// Scores `result` (the labels of `frame`) against `truth` and returns this frame's score
  /// (frames = 1); accumulate over frames with Score::operator+=. Throws
  /// std::invalid_argument when `result` is not sized for `frame`.
  Score score(const Frame& frame, const GroundResult& result, const GroundTruth& truth);

 private:
  struct Point {
    float x, y, z, range;
  };
  void collect(const Frame& frame, const GroundResult& result, const GroundTruth& truth,
               Score& score);
  void index_ground();
  float terrain_height(const Point& p);
  // Height of obstacle i above the terrain: exact when known, else estimated; NaN (counted
  // in obstacles_without_terrain) when neither.
  float obstacle_above_terrain_m(std::size_t i, Score& score);

  ScoreConfig config_;
  std::vector<Point> ground_;                           // truth-ground returns of the frame
  std::vector<Point> obstacles_;                        // truth-obstacle returns within the radius
  std::vector<std::uint8_t> obstacle_pred_;             // 1 = predicted ground
  std::vector<float> obstacle_exact_above_m_;           // exact height, NaN when unknown
  std::vector<std::uint32_t> grid_start_, grid_items_;  // ground by horizontal grid cell
  std::vector<std::uint32_t> sector_start_, sector_items_;  // ground by angular sector
  std::vector<std::uint32_t> cursor_;                       // counting-sort write positions
  std::vector<float> scratch_;                              // terrain heights around one obstacle
  int grid_side_ = 0;
};

/// Score of a whole capture under one detector configuration.
struct CaptureScore {
  std::string capture;  // file stem
  std::string method;  // to_string(DetectorConfig::method), or a caller's label
  Score score;
  double detect_ms_total = 0;  // wall time spent in GroundDetector::detect
};

struct CaptureScoreOptions {
  ScoreConfig score;
  int max_frames = 0;            // 0 = every frame
  bool skip_incomplete = false;  // leave out partial frames (start / end of capture)
  // Optional: called after every scored frame with the index of the detector configuration,
  // the frame, its labels and its score (per-frame reports, pictures with the truth).
  std::function<void(std::size_t detector, const Frame&, const GroundResult&, const Score&)>
      on_frame;
};

/// Reads `pcap_path` with a CaptureReader, detects ground in every frame with `detector` and
/// scores it against `labels_path` (with its heights file, GroundTruth::load_with_heights). Throws
/// std::runtime_error for unreadable files and std::invalid_argument for a bad configuration or
/// labels file.
CaptureScore score_capture(const std::filesystem::path& pcap_path,
                           const std::filesystem::path& labels_path, const DetectorConfig& detector,
                           double radius_m = 40.0);
CaptureScore score_capture(const std::filesystem::path& pcap_path,
                           const std::filesystem::path& labels_path, const DetectorConfig& detector,
                           const CaptureScoreOptions& options);

/// Same for several detector configurations at once: the capture is read and decoded once,
/// every frame goes through each detector in turn. One result per configuration, in order.
std::vector<CaptureScore> score_capture(const std::filesystem::path& pcap_path,
                                        const std::filesystem::path& labels_path,
                                        std::span<const DetectorConfig> detectors,
                                        const CaptureScoreOptions& options);

/// Extrinsics from a simulator `STEM.json` (mounting roll/pitch, sensor height), so the
/// vehicle frame has z = 0 on the ground under the sensor. Throws std::runtime_error.
Extrinsics load_sim_extrinsics(const std::filesystem::path& json_path);

/// Refuses ground truth that belongs to another capture (it would score a meaningless
/// figure): throws std::runtime_error unless `labels_path` holds 384 bytes per data packet
/// of a capture with `capture`'s counters, and, when `sim_json` exists, its "packets" count
/// describes the capture too. Every front-end's `eval` calls it before scoring.
void check_labels_match(const SourceCounters& capture, const std::filesystem::path& labels_path,
                        const std::filesystem::path& sim_json);

}  // namespace vlpground::eval
