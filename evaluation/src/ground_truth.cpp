// Ground-truth labels: loading, validation and the frame-cell -> wire-slot mapping.
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "vlpground/evaluation/evaluation.hpp"

namespace vlpground::eval {

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

GroundTruth GroundTruth::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error("ground truth: cannot open '" + path.string() + "'");
  }
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  if (in.bad()) {
    throw std::runtime_error("ground truth: error reading '" + path.string() + "'");
  }
  try {
    return GroundTruth(std::move(bytes));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(e.what()) + " in '" + path.string() + "'");
  }
}

TruthLabel GroundTruth::at(std::uint64_t packet, int slot) const {
  if (slot < 0 || slot >= kSlotsPerPacket || packet >= packets()) return TruthLabel::none;
  return static_cast<TruthLabel>(
      bytes_[packet * kSlotsPerPacket + static_cast<std::uint64_t>(slot)]);
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
  obstacles_without_terrain += o.obstacles_without_terrain;
  returns_without_truth += o.returns_without_truth;
  truth_without_return += o.truth_without_return;
  ambiguous_skipped += o.ambiguous_skipped;
  frames += o.frames;
  return *this;
}

}  // namespace vlpground::eval
