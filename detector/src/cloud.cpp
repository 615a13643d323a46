// Building the shared Cloud: every valid return, extrinsics applied, structure of arrays.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "method.hpp"
#include "vlpground_internal/vector_clones.hpp"

namespace vlpground {

RigidTransform vehicle_from_sensor(const Extrinsics& e) {
  constexpr double kDegToRad = M_PI / 180.0;
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(e.yaw_deg * kDegToRad, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(e.pitch_deg * kDegToRad, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(e.roll_deg * kDegToRad, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  RigidTransform out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.r[i][j] = static_cast<float>(r(i, j));
  out.t[0] = static_cast<float>(e.x_m);
  out.t[1] = static_cast<float>(e.y_m);
  out.t[2] = static_cast<float>(e.z_m);
  return out;
}

}  // namespace vlpground

namespace vlpground::detail {

namespace {

using Index = std::size_t;
using Transform = RigidTransform;

// One frame row: its cells and where its points go.
struct Row {
  const float *x, *y, *z;
  const std::uint8_t* valid;
  std::uint8_t layer_index;
  std::uint16_t ring;
  Index first_cell;
  int columns;
};

Row row_of(const Frame& frame, int layer, int ring) {
  const Index first = frame.index(ring, 0);
  const ReturnLayer& l = frame.layer[layer];
  return {l.x_m.data() + first,
          l.y_m.data() + first,
          l.z_m.data() + first,
          l.valid.data() + first,
          static_cast<std::uint8_t>(layer),
          static_cast<std::uint16_t>(ring),
          first,
          frame.columns()};
}

// Raw views of the cloud's arrays: stores through them cannot alias each other.
struct Out {
  float* __restrict x, * __restrict y, * __restrict z, * __restrict range_xy;
  std::uint32_t* __restrict cell;
  std::uint8_t* __restrict layer, * __restrict twin;
  std::uint16_t* __restrict ring, * __restrict column;
  std::uint32_t* __restrict last_rows;
};

Out view(Cloud& c) {
  return {c.x.data(),     c.y.data(),    c.z.data(),    c.range_xy.data(), c.cell.data(),
          c.layer.data(), c.twin.data(), c.ring.data(), c.column.data(),   c.last_rows.data()};
}

// Copies the sensor-frame point of cell `col` of `row` to slot k (whether or not it is
// kept); transform_points moves it to the vehicle frame afterwards.
inline void write_point(const Row& row, int col, Index k, const Out& o) {
  o.x[k] = row.x[col];
  o.y[k] = row.y[col];
  o.z[k] = row.z[col];
  o.cell[k] = static_cast<std::uint32_t>(row.first_cell + static_cast<Index>(col));
  o.layer[k] = row.layer_index;
  o.ring[k] = row.ring;
  o.column[k] = static_cast<std::uint16_t>(col);
}

// Branchless compaction: every cell is written at slot k, which advances only past valid
// cells (so the arrays have one spare slot at the end). Returns the next free slot.
VLPGROUND_VECTOR_CLONES
Index append_row(const Row row, Index k, const Out o) {
  for (int col = 0; col < row.columns; ++col) {
    write_point(row, col, k, o);
    k += row.valid[col];
  }
  return k;
}

// p = R s + t and the horizontal range from the sensor, for points [0, n) in place.
VLPGROUND_VECTOR_CLONES
void transform_points(const Transform tr, Index n, const Out o) {
  const float(&r)[3][3] = tr.r;
  for (Index k = 0; k < n; ++k) {
    const float sx = o.x[k], sy = o.y[k], sz = o.z[k];
    const float px = r[0][0] * sx + r[0][1] * sy + r[0][2] * sz + tr.t[0];
    const float py = r[1][0] * sx + r[1][1] * sy + r[1][2] * sz + tr.t[1];
    const float pz = r[2][0] * sx + r[2][1] * sy + r[2][2] * sz + tr.t[2];
    const double dx = px - tr.t[0], dy = py - tr.t[1];
    o.x[k] = px;
    o.y[k] = py;
    o.z[k] = pz;
    o.range_xy[k] = static_cast<float>(std::sqrt(dx * dx + dy * dy));  // what hypotf computes
  }
}

// A last-layer row of a deduplicated cloud: a cell repeating the strongest echo exactly
// (same point) adds no point; its strongest twin k0 is marked and stands for it in
// last_rows (slot p). k0 walks the strongest points of the same row. Most cells repeat
// the strongest echo, so the branch is well predicted.
VLPGROUND_VECTOR_CLONES
Index append_last_row(const Row row, const Row strongest, const std::uint8_t* same_echo, Index k,
                      Index k0, Index& p, const Out o) {
  constexpr int kChunk = 256;
  std::uint8_t dup[kChunk];
  for (int first = 0; first < row.columns; first += kChunk) {
    const int count = std::min(kChunk, row.columns - first);
    // Which cells repeat the strongest echo, as one vectorisable pass.
    for (int c = 0; c < count; ++c) {
      const int col = first + c;
      const bool same_point = (row.x[col] == strongest.x[col]) & (row.y[col] == strongest.y[col]) &
                              (row.z[col] == strongest.z[col]);
      dup[c] = static_cast<std::uint8_t>(
          ((same_echo[col] & strongest.valid[col] & row.valid[col]) != 0) & same_point);
    }
    for (int c = 0; c < count; ++c) {
      const int col = first + c;
      if (dup[c] != 0) {
        o.twin[k0] = 1;
        o.last_rows[p++] = static_cast<std::uint32_t>(k0);
      } else {
        write_point(row, col, k, o);
        o.last_rows[p] = static_cast<std::uint32_t>(k);
        p += row.valid[col];
        k += row.valid[col];
      }
      k0 += strongest.valid[col];
    }
  }
  return k;
}

Index count_valid(const Frame& frame, int layer) {
  Index n = 0;
  for (int ring = 0; ring < kLasers; ++ring) {
    const std::uint8_t* v = frame.layer[layer].valid.data() + frame.index(ring, 0);
    for (int col = 0; col < frame.columns(); ++col) n += v[col];
  }
  return n;
}

void resize_all(Cloud& c, Index n) {
  for (auto* v : {&c.x, &c.y, &c.z, &c.range_xy}) v->resize(n);
  c.cell.resize(n);
  c.layer.resize(n);
  c.ring.resize(n);
  c.column.resize(n);
  c.twin.resize(n);
}

}  // namespace

void build_cloud(const Frame& frame, const Extrinsics& extrinsics, bool deduplicate, Cloud& cloud) {
  // Sized, not cleared: every slot is written below, so only growth initialises memory.
  cloud.last_begin = 0;
  const Transform tr = vehicle_from_sensor(extrinsics);
  const int layers = frame.layers();
  cloud.deduplicated = deduplicate && layers == 2;
  const Index strongest = count_valid(frame, 0), last = layers == 2 ? count_valid(frame, 1) : 0;
  resize_all(cloud, strongest + last + 1);
  std::fill(cloud.twin.begin(), cloud.twin.end(), std::uint8_t{0});
  if (cloud.deduplicated) cloud.last_rows.resize(last + 1);
  const Out out = view(cloud);
  Index k = 0, p = 0, row_start[kLasers] = {};
  for (int l = 0; l < layers; ++l) {
    if (l == 1) cloud.last_begin = k;
    for (int ring = 0; ring < kLasers; ++ring) {
      const Row row = row_of(frame, l, ring);
      if (l == 0) row_start[ring] = k;
      k = l == 1 && cloud.deduplicated
              ? append_last_row(row, row_of(frame, 0, ring),
                                frame.same_echo.data() + row.first_cell, k, row_start[ring], p, out)
              : append_row(row, k, out);
    }
  }
  transform_points(tr, k, out);
  resize_all(cloud, k);
  cloud.last_rows.resize(p);
}

RingRuns point_ring_runs(const Cloud& cloud, Index first, Index last) {
  return ring_runs(first, last, [&](Index p) { return int{cloud.ring[p]}; });
}

Index strongest_end(const Cloud& cloud) {
  if (cloud.deduplicated) return cloud.last_begin;
  // Layers ascend through the cloud: a binary search for the first last-layer point.
  return static_cast<Index>(std::partition_point(cloud.layer.begin(), cloud.layer.end(),
                                                 [](std::uint8_t l) { return l == 0; }) -
                            cloud.layer.begin());
}

RingRuns last_row_runs(const Cloud& cloud) {
  return ring_runs(0, cloud.last_rows.size(),
                   [&](Index p) { return int{cloud.ring[cloud.last_rows[p]]}; });
}

Index last_row_position(const Cloud& cloud, const RingRuns& runs, int ring, int column) {
  const auto& rows = cloud.last_rows;
  const auto r = static_cast<Index>(ring);
  const auto end = rows.begin() + static_cast<std::ptrdiff_t>(runs[r + 1]);
  const auto it =
      std::partition_point(rows.begin() + static_cast<std::ptrdiff_t>(runs[r]), end,
                           [&](std::uint32_t p) { return int{cloud.column[p]} < column; });
  if (it == end || int{cloud.column[*it]} != column) return rows.size();
  return static_cast<Index>(it - rows.begin());
}

}  // namespace vlpground::detail
