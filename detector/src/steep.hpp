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

}  // namespace vlpground::detail
