// Returns on steep surfaces (walls, car sides, poles), found across rings: on the ground the
// next ring of the same column lands metres farther away, on a vertical surface it lands
// straight above. Such a return cannot be a ground inlier and is never labelled ground.
#pragma once

#include <cstdint>
#include <vector>

#include "method.hpp"

namespace vlpground::detail {

/// steep[i] = 1 when the surface between cloud point i and the return of the ring just
/// above or just below it (same column, same layer) rises more than 45 degrees
/// (|dz| > |d horizontal range from the sensor|, vehicle frame). One merge pass over
/// adjacent rows; requires the cloud in build_cloud order (layer, ring, column ascending).
void mark_steep(const Cloud& cloud, std::vector<std::uint8_t>& steep);

/// Scratch of add_faces_across_gaps, kept by the caller so that no frame allocates.
struct FaceTable {
  std::vector<std::uint16_t> present;  // by column: a bit per ring that returned
  std::vector<std::uint32_t> point;    // by ring, then column: the cloud point
};

/// Sets steep[i] = 1 also where the ring just above or below cloud point i did not return in
/// its column (same layer) and i and the return of the ring beyond lie on one upright face:
/// the same horizontal range within 0.1 m, rising over 63 degrees. A face whose lowest
/// return's next ring dropped out (a dark car side) is then still a face. The column
/// profiles use these flags; level 1 and the cells use mark_steep's alone.
void add_faces_across_gaps(const Cloud& cloud, FaceTable& table, std::vector<std::uint8_t>& steep);

}  // namespace vlpground::detail
