// Building the shared Cloud: every valid return, extrinsics applied, structure of arrays.
#include <Eigen/Geometry>
#include <cmath>

#include "method.hpp"

namespace vlpground::detail {

void Cloud::clear() {
  x.clear();
  y.clear();
  z.clear();
  range_xy.clear();
  cell.clear();
  layer.clear();
  ring.clear();
  column.clear();
}

namespace {

// Vehicle-from-sensor rotation R = Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3f rotation_of(const Extrinsics& e) {
  constexpr double kDegToRad = M_PI / 180.0;
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(e.yaw_deg * kDegToRad, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(e.pitch_deg * kDegToRad, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(e.roll_deg * kDegToRad, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return r.cast<float>();
}

}  // namespace

void build_cloud(const Frame& frame, const Extrinsics& extrinsics, Cloud& cloud) {
  cloud.clear();
  const Eigen::Matrix3f r = rotation_of(extrinsics);
  const Eigen::Vector3f t(static_cast<float>(extrinsics.x_m), static_cast<float>(extrinsics.y_m),
                          static_cast<float>(extrinsics.z_m));
  const int columns = frame.columns();
  for (int l = 0; l < frame.layers(); ++l) {
    const ReturnLayer& layer = frame.layer[l];
    for (int ring = 0; ring < kLasers; ++ring) {
      for (int col = 0; col < columns; ++col) {
        const std::size_t i = frame.index(ring, col);
        if (layer.valid[i] == 0) continue;
        const Eigen::Vector3f p = r * Eigen::Vector3f(layer.x_m[i], layer.y_m[i], layer.z_m[i]) + t;
        cloud.x.push_back(p.x());
        cloud.y.push_back(p.y());
        cloud.z.push_back(p.z());
        cloud.range_xy.push_back(std::hypot(p.x() - t.x(), p.y() - t.y()));
        cloud.cell.push_back(static_cast<std::uint32_t>(i));
        cloud.layer.push_back(static_cast<std::uint8_t>(l));
        cloud.ring.push_back(static_cast<std::uint16_t>(ring));
        cloud.column.push_back(static_cast<std::uint16_t>(col));
      }
    }
  }
}

}  // namespace vlpground::detail
