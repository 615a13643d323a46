// Plane hypotheses for the tangent method: seeded sampling from the lowest returns of each
// bin, with tilt and tangent checks, and least-squares refinement.
#pragma once

#include <cstdint>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"

namespace vlpground::detail {

/// Hypotheses as structure of arrays (unit normal with nz > 0, offset d).
struct PlaneSet {
  std::vector<float> nx, ny, nz, d;
  [[nodiscard]] std::size_t size() const { return nx.size(); }
  void clear();
  void push(const Plane& p);
  [[nodiscard]] Plane at(std::size_t i) const { return {nx[i], ny[i], nz[i], d[i]}; }
};

/// splitmix64: tiny, seedable, identical on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform-ish integer in [0, n) (modulo bias is negligible for n << 2^64).
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
  /// Steps over `draws` draws whose values would go unused (the state only counts them).
  void skip(std::uint64_t draws) { state_ += draws * 0x9E3779B97F4A7C15ull; }

 private:
  std::uint64_t state_;
};

/// Low points: one per occupied bin (the lowest return with a tangent), with bin coords.
struct LowPoints {
  std::vector<float> x, y, z, tx, ty, tz;
  std::vector<std::int32_t> slot_of_bin;  // B*B, -1 = no low point
  std::vector<std::int32_t> col, row;
};

struct SamplingParams {
  int bins = 80;
  int hypotheses = 200;
  int neighbour_bins = 10;   // the 2nd and 3rd points come from within this many bins
  float min_area_m2 = 1.0f;  // triangles smaller than this are ill-conditioned
  float min_nz = 0.978f;     // cos(max tilt)
  float sin_delta = 0.17f;   // eq. 3 on the three sample tangents
  std::uint64_t seed = 1;
};

/// Samples up to `hypotheses` planes (fewer only when too few low points exist).
void sample_hypotheses(const LowPoints& low, const SamplingParams& params, PlaneSet& out);

/// Plane through three points with nz >= 0; false when degenerate.
bool plane_from_points(const float* a, const float* b, const float* c, Plane& out,
                       float min_area_m2);

/// Accumulates points for a least-squares plane (smallest eigenvector of the covariance).
class PlaneFit {
 public:
  /// Adds the point `weight` times (inline: refinement adds every inlier of a frame).
  void add(float x, float y, float z, int weight = 1) {
    const double p[3] = {x, y, z};
    for (int copy = 0; copy < weight; ++copy) {
      for (int k = 0; k < 3; ++k) s_[k] += p[k];
      ss_[0] += p[0] * p[0];
      ss_[1] += p[0] * p[1];
      ss_[2] += p[0] * p[2];
      ss_[3] += p[1] * p[1];
      ss_[4] += p[1] * p[2];
      ss_[5] += p[2] * p[2];
    }
    n_ += weight;
  }
  [[nodiscard]] int count() const { return n_; }
  /// False with fewer than 3 points or a degenerate spread.
  bool solve(Plane& out) const;

 private:
  double s_[3] = {0, 0, 0};
  double ss_[6] = {0, 0, 0, 0, 0, 0};  // xx xy xz yy yz zz
  int n_ = 0;
};

}  // namespace vlpground::detail
