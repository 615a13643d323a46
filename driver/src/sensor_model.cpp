#include "vlpground/driver/sensor_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace vlpground {
namespace {

// Elevation by laser id (firing order), degrees: the VLP-16 and Puck Hi-Res manuals.
constexpr std::array<double, kLasers> kVlp16ElevationDeg = {-15, 1, -13, 3,  -11, 5,  -9, 7,
                                                            -7,  9, -5,  11, -3,  13, -1, 15};
constexpr std::array<double, kLasers> kHiResElevationDeg = {-10.00, 0.67, -8.67, 2.00, -7.33, 3.33,
                                                            -6.00,  4.67, -4.67, 6.00, -3.33, 7.33,
                                                            -2.00,  8.67, -0.67, 10.00};

// Vertical offset by laser id, millimetres (VLP-16 manual). The reference decodes of the
// Hi-Res capture (`urban_hires_last.expected.csv`, fitted over ranges 5..50 m to 0.1 mm)
// add these same offsets to the Hi-Res elevations, not values scaled to +-7.4 mm, so both
// models share them; the difference would be under 4 mm.
constexpr std::array<double, kLasers> kVerticalOffsetMm = {
    11.2, -0.7, 9.7, -2.2, 8.1, -3.7, 6.6, -5.1, 5.1, -6.6, 3.7, -8.1, 2.2, -9.7, 0.7, -11.2};

}  // namespace

SensorModel SensorModel::builtin(Model model) {
  SensorModel m;
  m.model = model;
  const auto& elevation = model == Model::hires ? kHiResElevationDeg : kVlp16ElevationDeg;
  for (std::size_t i = 0; i < m.lasers.size(); ++i) {
    m.lasers[i].elevation_deg = elevation[i];
    m.lasers[i].vertical_offset_m = kVerticalOffsetMm[i] / 1000.0;
  }
  m.finalize();
  return m;
}

void SensorModel::finalize() {
  for (auto& laser : lasers) {
    const double rad = laser.elevation_deg * std::numbers::pi / 180.0;
    laser.cos_elevation = std::cos(rad);
    laser.sin_elevation = std::sin(rad);
    const double rot = laser.azimuth_offset_deg * std::numbers::pi / 180.0;
    laser.cos_azimuth_offset = std::cos(rot);
    laser.sin_azimuth_offset = std::sin(rot);
  }
  std::array<std::uint8_t, kLasers> order{};
  std::iota(order.begin(), order.end(), std::uint8_t{0});
  std::stable_sort(order.begin(), order.end(), [this](std::uint8_t a, std::uint8_t b) {
    return lasers[a].elevation_deg < lasers[b].elevation_deg;
  });
  for (std::size_t ring = 0; ring < order.size(); ++ring) {
    laser_of_ring[ring] = order[ring];
    ring_of_laser[order[ring]] = static_cast<std::uint8_t>(ring);
  }
}

}  // namespace vlpground
