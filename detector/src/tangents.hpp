// Per-return tangent along its ring (paper Sec. III-A): numerical differentiation between
// neighbours of the same row of the range image.
#pragma once

#include <cstdint>
#include <vector>

#include "method.hpp"

namespace vlpground::detail {

struct TangentParams {
  int max_span_columns = 16;     // how far along the row a neighbour may be
  float target_chord_m = 0.2f;   // walk outwards until a neighbour is this far away
  float min_chord_m = 0.08f;     // shorter baselines are too noisy: no tangent
  float jump_abs_m = 0.15f;      // range step refused as a discontinuity when larger than
  float jump_rel = 0.03f;        //   jump_abs_m + jump_rel * range (per step along the row)
  float column_angle_rad = 0.f;  // azimuth step between columns; > 0 enables the fast path
};

/// Unit tangents, one per cloud point. Returns without a trustworthy tangent get
/// valid = 0 and t = (0, 0, kNoTangentZ), so that |n . t| exceeds sin(delta) for every
/// near-horizontal plane and the eq. 3 test fails without a branch.
struct Tangents {
  std::vector<float> x, y, z;
  std::vector<std::uint8_t> valid;
  std::vector<std::uint16_t> step;  // scratch: fast-path column step per point
  std::vector<std::uint32_t> before, after;  // scratch: each point's neighbours along its row
};

inline constexpr float kNoTangentZ = 4.0f;

/// Eq. 3 of the paper: |n.x + d| < eps and |pi/2 - arccos(n.t)| < delta. For a unit t,
/// |pi/2 - arccos(n.t)| = |arcsin(n.t)|, so the angle test is |n.t| < sin(delta).
inline bool eq3_inlier(const Plane& p, float x, float y, float z, float tx, float ty, float tz,
                       float eps, float sin_delta) {
  const float dist = p.nx * x + p.ny * y + p.nz * z + p.d;
  const float dot = p.nx * tx + p.ny * ty + p.nz * tz;
  return (dist < 0 ? -dist : dist) < eps && (dot < 0 ? -dot : dot) < sin_delta;
}

/// Requires the cloud in build_cloud order (layer, ring, column ascending).
void compute_tangents(const Cloud& cloud, const TangentParams& params, Tangents& out);

}  // namespace vlpground::detail
