// Plausibility of the four segment planes once Algorithm 1 has chosen them
// (docs/detector.md, additions 3-5 and I): sensor-height prior, agreement at the partition
// centre and along shared edges, and inheritance by segments without ground of their own.
#pragma once

#include <cstdint>

#include "partition_search.hpp"
#include "scoring.hpp"
#include "vlpground/detector/ground_detector.hpp"

namespace vlpground::detail {

/// Signed distance of (x, y, z) from p (positive above it).
inline float signed_height(const Plane& p, float x, float y, float z) {
  return p.nx * x + p.ny * y + p.nz * z + p.d;
}

/// The mounting height is known (extrinsics z, at least the minimum sensor height): the
/// vehicle frame's z = 0 is then the ground under the wheels.
[[nodiscard]] inline bool mounting_height_known(float z_m, float min_sensor_height_m) {
  return z_m > 0.f && z_m >= min_sensor_height_m;
}

struct AgreementRules {
  float origin_x = 0, origin_y = 0, sensor_z = 0;  // sensor position in the vehicle frame
  double min_sensor_height_m = 0.5, max_sensor_height_m = 5.0;
  double max_step_m = 0.4;  // adjacent planes must meet within this
  float soft_m = 2.f;       // ... somewhere within this of the centre or the shared edge
  float radius_m = 40.f;    // edges are compared inside the fit radius only
  // With the mounting height known, a plane passing more than this over the ground under
  // the wheels, at the sensor, is not the ground the vehicle stands on: the roofs of the
  // cars around it in a jam, 1.3-1.6 m up (jam_s7003 at Hi-Res, where they were the only
  // plane found). A ramp's plane extrapolated over the level ground at its foot passes up
  // to 1.06 m over it (garage_s405 at 5 Hz).
  double max_over_wheels_m = 1.2;
};

/// The anchor is the best-scoring segment whose plane lies a sensor height under the
/// sensor (none: no segment has ground); the segment under the sensor must pass the same
/// prior; every other plane must meet the anchor's near the centre, and adjacent planes
/// each other along their shared edge (the higher one, never the anchor, loses).
/// Clears GroundSegment::has_ground of the segments that fail.
void check_agreement(const SearchResult& found, const AgreementRules& rules, GroundResult& out);

/// What a segment's own returns say about a plane: the scoring candidates of its bins.
struct SegmentEvidence {
  const Candidates* candidates = nullptr;
  const std::int32_t* bin_slot = nullptr;  // B*B, -1 = empty bin
  int bins = 0;
  ScoreParams score;
};

/// A segment without ground inherits the plane of the neighbour that explains its own
/// returns best (net score b_m over its candidates; ties: the better-scoring neighbour).
void inherit_planes(const SearchResult& found, const SegmentEvidence& evidence, GroundResult& out);

}  // namespace vlpground::detail
