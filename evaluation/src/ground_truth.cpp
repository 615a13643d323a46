// Ground-truth labels and heights: loading, validation and the frame-cell -> wire-slot
// mapping.
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "vlpground/evaluation/evaluation.hpp"

namespace vlpground::eval {
namespace {

// The whole file; std::runtime_error naming it (and what it is) when it cannot be read.
std::vector<std::uint8_t> read_file(const std::filesystem::path& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error(std::string(what) + ": cannot open '" + path.string() + "'");
  }
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  if (in.bad()) {
    throw std::runtime_error(std::string(what) + ": error reading '" + path.string() + "'");
  }
  return bytes;
}

// Little-endian int16 values; the caller has checked that the size is even.
std::vector<std::int16_t> decode_heights_cm(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::int16_t> out(bytes.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::uint8_t le[2];
    std::memcpy(le, bytes.data() + 2 * i, sizeof le);
    out[i] = static_cast<std::int16_t>(static_cast<std::uint16_t>(le[0] | (le[1] << 8)));
  }
  return out;
}

// make(), its std::invalid_argument naming `path`.
template <class Make>
GroundTruth with_file_name(const std::filesystem::path& path, Make&& make) {
  try {
    return make();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(e.what()) + " in '" + path.string() + "'");
  }
}

}  // namespace

std::filesystem::path heights_path_beside(const std::filesystem::path& labels_path) {
  return std::filesystem::path(labels_path).replace_extension(".heights");
}

GroundTruth::GroundTruth(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {
  if (bytes_.size() % kSlotsPerPacket != 0) {
    throw std::invalid_argument("ground truth: size " + std::to_string(bytes_.size()) +
                                " bytes is not a multiple of 384 (12 blocks x 32 slots)");
  }
  for (std::size_t i = 0; i < bytes_.size(); ++i) {
    if (bytes_[i] > static_cast<std::uint8_t>(TruthLabel::ambiguous)) {
      throw std::invalid_argument("ground truth: byte " + std::to_string(i) + " has value " +
                                  std::to_string(bytes_[i]) + ", expected 0..3");
    }
  }
}

GroundTruth::GroundTruth(std::vector<std::uint8_t> bytes, std::vector<std::int16_t> heights_cm)
    : GroundTruth(std::move(bytes)) {
  if (heights_cm.size() != bytes_.size()) {
    throw std::invalid_argument("ground truth heights: " + std::to_string(heights_cm.size()) +
                                " heights for " + std::to_string(bytes_.size()) +
                                " label slots (one int16 per slot expected)");
  }
  heights_cm_ = std::move(heights_cm);
}

GroundTruth GroundTruth::load(const std::filesystem::path& path) {
  std::vector<std::uint8_t> bytes = read_file(path, "ground truth");
  return with_file_name(path, [&] { return GroundTruth(std::move(bytes)); });
}

GroundTruth GroundTruth::load(const std::filesystem::path& labels_path,
                              const std::filesystem::path& heights_path) {
  GroundTruth labels = load(labels_path);
  const std::vector<std::uint8_t> raw = read_file(heights_path, "ground truth heights");
  if (raw.size() != 2 * labels.bytes_.size()) {
    throw std::invalid_argument(
        "ground truth heights: '" + heights_path.string() + "' has " + std::to_string(raw.size()) +
        " bytes, expected " + std::to_string(2 * labels.bytes_.size()) + " (2 per slot of the " +
        std::to_string(labels.bytes_.size()) + " slots of '" + labels_path.string() + "')");
  }
  labels.heights_cm_ = decode_heights_cm(raw);
  return labels;
}

GroundTruth GroundTruth::load_with_heights(const std::filesystem::path& labels_path) {
  const std::filesystem::path heights = heights_path_beside(labels_path);
  if (std::filesystem::exists(heights)) return load(labels_path, heights);
  return load(labels_path);
}

TruthLabel GroundTruth::at(std::uint64_t packet, int slot) const {
  if (slot < 0 || slot >= kSlotsPerPacket || packet >= packets()) return TruthLabel::none;
  return static_cast<TruthLabel>(
      bytes_[packet * kSlotsPerPacket + static_cast<std::uint64_t>(slot)]);
}

std::optional<float> GroundTruth::height_above_terrain_m(std::uint64_t packet, int slot) const {
  if (!has_heights() || slot < 0 || slot >= kSlotsPerPacket || packet >= packets()) {
    return std::nullopt;
  }
  const std::int16_t cm = heights_cm_[packet * kSlotsPerPacket + static_cast<std::uint64_t>(slot)];
  return static_cast<float>(cm) / 100.0f;
}

SlotRef slot_of_cell(const Frame& frame, int ring, int col, int layer) {
  const auto c = static_cast<std::size_t>(col);
  const int j = frame.column_in_packet[c];
  const int laser = frame.laser_of_ring[ring];
  SlotRef ref;
  ref.packet = frame.column_packet_index[c];
  ref.channel = (j % 2) * 16 + laser;
  if (frame.meta.mode == ReturnMode::dual) {
    const int pair = j / 2;
    ref.block = layer == kLastLayer ? 2 * pair : 2 * pair + 1;
  } else {
    ref.block = j / 2;
  }
  return ref;
}

double Confusion::precision() const {
  return tp + fp == 0 ? 0.0 : static_cast<double>(tp) / static_cast<double>(tp + fp);
}

double Confusion::recall() const {
  return tp + fn == 0 ? 0.0 : static_cast<double>(tp) / static_cast<double>(tp + fn);
}

double Confusion::f1() const {
  const auto denominator = 2 * tp + fp + fn;
  return denominator == 0 ? 0.0 : 2.0 * static_cast<double>(tp) / static_cast<double>(denominator);
}

Confusion& Confusion::operator+=(const Confusion& o) {
  tp += o.tp;
  fp += o.fp;
  fn += o.fn;
  tn += o.tn;
  return *this;
}

std::string_view to_string(TerrainSource source) {
  switch (source) {
    case TerrainSource::exact:
      return "exact";
    case TerrainSource::estimated:
      return "estimated";
    case TerrainSource::mixed:
      return "mixed";
    case TerrainSource::none:
      break;
  }
  return "none";
}

TerrainSource Score::terrain_source() const {
  if (obstacles_exact_terrain == 0) {
    return obstacles_estimated_terrain == 0 ? TerrainSource::none : TerrainSource::estimated;
  }
  return obstacles_estimated_terrain == 0 ? TerrainSource::exact : TerrainSource::mixed;
}

double Score::high_obstacle_as_ground_rate() const {
  return high_obstacles == 0
             ? 0.0
             : static_cast<double>(high_obstacles_as_ground) / static_cast<double>(high_obstacles);
}

Score& Score::operator+=(const Score& o) {
  all += o.all;
  near_band += o.near_band;
  far_band += o.far_band;
  high_obstacles += o.high_obstacles;
  high_obstacles_as_ground += o.high_obstacles_as_ground;
  obstacles_exact_terrain += o.obstacles_exact_terrain;
  obstacles_estimated_terrain += o.obstacles_estimated_terrain;
  obstacles_without_terrain += o.obstacles_without_terrain;
  returns_without_truth += o.returns_without_truth;
  truth_without_return += o.truth_without_return;
  ambiguous_skipped += o.ambiguous_skipped;
  frames += o.frames;
  return *this;
}

}  // namespace vlpground::eval
