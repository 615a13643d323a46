// Per-frame scoring: confusion counts by range band and the high-obstacle-as-ground rate.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "vlpground/evaluation/evaluation.hpp"

namespace vlpground::eval {
namespace {

void require_positive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("ScoreConfig: ") + name + " must be > 0 (got " +
                                std::to_string(value) + ")");
  }
}

float azimuth_deg(float x, float y) {
  const float deg = std::atan2(y, x) * (180.0f / std::numbers::pi_v<float>);
  return deg < 0.0f ? deg + 360.0f : deg;
}

void count(Confusion& c, bool truth_ground, bool predicted_ground) {
  if (truth_ground) {
    ++(predicted_ground ? c.tp : c.fn);
  } else {
    ++(predicted_ground ? c.fp : c.tn);
  }
}

}  // namespace

void ScoreConfig::validate() const {
  require_positive(radius_m, "radius_m");
  require_positive(band_split_m, "band_split_m");
  require_positive(high_obstacle_m, "high_obstacle_m");
  require_positive(terrain_radius_m, "terrain_radius_m");
  require_positive(sector_deg, "sector_deg");
  if (sector_deg > 360.0) {
    throw std::invalid_argument("ScoreConfig: sector_deg must be <= 360");
  }
}

FrameScorer::FrameScorer(const ScoreConfig& config) : config_(config) {
  config_.validate();
  grid_side_ = static_cast<int>(
      std::ceil(2.0 * (config_.radius_m + config_.terrain_radius_m) / config_.terrain_radius_m));
  grid_start_.resize(static_cast<std::size_t>(grid_side_ * grid_side_) + 1);
  sector_start_.resize(static_cast<std::size_t>(std::ceil(360.0 / config_.sector_deg)) + 1);
}

Score FrameScorer::score(const Frame& frame, const GroundResult& result, const GroundTruth& truth) {
  Score score;
  score.frames = 1;
  ground_.clear();
  obstacles_.clear();
  obstacle_pred_.clear();
  obstacle_exact_above_m_.clear();
  collect(frame, result, truth, score);
  index_ground();
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    const float above = obstacle_above_terrain_m(i, score);
    if (above > static_cast<float>(config_.high_obstacle_m)) {  // false for NaN
      ++score.high_obstacles;
      score.high_obstacles_as_ground += obstacle_pred_[i];
    }
  }
  return score;
}

float FrameScorer::obstacle_above_terrain_m(std::size_t i, Score& score) {
  const float exact = obstacle_exact_above_m_[i];
  if (!std::isnan(exact)) {
    ++score.obstacles_exact_terrain;
    return exact;
  }
  const float terrain = terrain_height(obstacles_[i]);
  if (std::isnan(terrain)) {
    ++score.obstacles_without_terrain;
    return terrain;
  }
  ++score.obstacles_estimated_terrain;
  return obstacles_[i].z - terrain;
}

void FrameScorer::collect(const Frame& frame, const GroundResult& result, const GroundTruth& truth,
                          Score& score) {
  const int layers = frame.layers();
  const std::size_t needed =
      static_cast<std::size_t>(kLasers - 1) * static_cast<std::size_t>(result.stride) +
      static_cast<std::size_t>(frame.columns());
  for (int layer = 0; layer < layers; ++layer) {
    if (result.stride < frame.columns() || result.label[layer].size() < needed) {
      throw std::invalid_argument("FrameScorer: result is not sized for this frame");
    }
  }
  const auto radius = static_cast<float>(config_.radius_m);
  const auto split = static_cast<float>(config_.band_split_m);
  for (int layer = 0; layer < layers; ++layer) {
    const ReturnLayer& returns = frame.layer[layer];
    for (int ring = 0; ring < kLasers; ++ring) {
      for (int col = 0; col < frame.columns(); ++col) {
        if (frame.column_valid[static_cast<std::size_t>(col)] == 0) continue;
        const std::size_t cell = frame.index(ring, col);
        if (layer == kLastLayer && frame.same_echo[cell] != 0) continue;  // counted in layer 0
        const SlotRef slot = slot_of_cell(frame, ring, col, layer);
        const TruthLabel label = truth.at(slot.packet, slot.slot());
        const bool has_return = returns.valid[cell] != 0;
        if (!has_return) {
          score.truth_without_return += label != TruthLabel::none;
          continue;
        }
        if (label == TruthLabel::none) {
          ++score.returns_without_truth;
          continue;
        }
        if (label == TruthLabel::ambiguous) {
          ++score.ambiguous_skipped;
          continue;
        }
        const Point p{returns.x_m[cell], returns.y_m[cell], returns.z_m[cell],
                      std::hypot(returns.x_m[cell], returns.y_m[cell])};
        const bool truth_ground = label == TruthLabel::ground;
        if (truth_ground) ground_.push_back(p);
        if (p.range >= radius) continue;
        const std::size_t out =
            static_cast<std::size_t>(ring) * static_cast<std::size_t>(result.stride) +
            static_cast<std::size_t>(col);
        const bool predicted_ground =
            result.label[layer][out] == static_cast<std::uint8_t>(GroundLabel::ground);
        count(score.all, truth_ground, predicted_ground);
        count(p.range < split ? score.near_band : score.far_band, truth_ground, predicted_ground);
        if (!truth_ground) {
          obstacles_.push_back(p);
          obstacle_pred_.push_back(predicted_ground ? 1 : 0);
          obstacle_exact_above_m_.push_back(truth.height_above_terrain_m(slot.packet, slot.slot())
                                                .value_or(std::numeric_limits<float>::quiet_NaN()));
        }
      }
    }
  }
}

// Counting sort of the truth-ground returns into a horizontal grid (cell = terrain radius,
// so a query looks at 3 x 3 cells) and into angular sectors (the fallback).
void FrameScorer::index_ground() {
  const double half = config_.radius_m + config_.terrain_radius_m;
  const auto cell_of = [&](const Point& p) -> int {
    const int gx = static_cast<int>(std::floor((p.x + half) / config_.terrain_radius_m));
    const int gy = static_cast<int>(std::floor((p.y + half) / config_.terrain_radius_m));
    if (gx < 0 || gy < 0 || gx >= grid_side_ || gy >= grid_side_) return -1;
    return gy * grid_side_ + gx;
  };
  const auto sectors = static_cast<int>(sector_start_.size()) - 1;
  const auto sector_of = [&](const Point& p) {
    const int s = static_cast<int>(azimuth_deg(p.x, p.y) / static_cast<float>(config_.sector_deg));
    return std::clamp(s, 0, sectors - 1);
  };
  const auto bucket = [&](std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items,
                          auto&& key) {
    std::fill(start.begin(), start.end(), 0u);
    for (const Point& p : ground_) {
      const int k = key(p);
      if (k >= 0) ++start[static_cast<std::size_t>(k) + 1];
    }
    for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    items.resize(start.back());
    cursor_.assign(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < ground_.size(); ++i) {
      const int k = key(ground_[i]);
      if (k < 0) continue;
      items[cursor_[static_cast<std::size_t>(k)]++] = static_cast<std::uint32_t>(i);
    }
  };
  bucket(grid_start_, grid_items_, cell_of);
  bucket(sector_start_, sector_items_, sector_of);
}

float FrameScorer::terrain_height(const Point& p) {
  const double half = config_.radius_m + config_.terrain_radius_m;
  const int gx = static_cast<int>(std::floor((p.x + half) / config_.terrain_radius_m));
  const int gy = static_cast<int>(std::floor((p.y + half) / config_.terrain_radius_m));
  const auto r2 = static_cast<float>(config_.terrain_radius_m * config_.terrain_radius_m);
  scratch_.clear();
  for (int y = std::max(gy - 1, 0); y <= std::min(gy + 1, grid_side_ - 1); ++y) {
    for (int x = std::max(gx - 1, 0); x <= std::min(gx + 1, grid_side_ - 1); ++x) {
      const auto c = static_cast<std::size_t>(y * grid_side_ + x);
      for (std::uint32_t k = grid_start_[c]; k < grid_start_[c + 1]; ++k) {
        const Point& g = ground_[grid_items_[k]];
        const float dx = g.x - p.x, dy = g.y - p.y;
        if (dx * dx + dy * dy < r2) scratch_.push_back(g.z);
      }
    }
  }
  if (!scratch_.empty()) {
    const auto mid = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
    std::nth_element(scratch_.begin(), mid, scratch_.end());
    return *mid;  // median (the upper one for an even count)
  }
  const auto sectors = static_cast<int>(sector_start_.size()) - 1;
  const int s =
      std::clamp(static_cast<int>(azimuth_deg(p.x, p.y) / static_cast<float>(config_.sector_deg)),
                 0, sectors - 1);
  float best_gap = std::numeric_limits<float>::infinity();
  float best_z = std::numeric_limits<float>::quiet_NaN();
  for (std::uint32_t k = sector_start_[static_cast<std::size_t>(s)];
       k < sector_start_[static_cast<std::size_t>(s) + 1]; ++k) {
    const Point& g = ground_[sector_items_[k]];
    const float gap = std::abs(g.range - p.range);
    if (gap < best_gap) {
      best_gap = gap;
      best_z = g.z;
    }
  }
  return best_z;
}

}  // namespace vlpground::eval
