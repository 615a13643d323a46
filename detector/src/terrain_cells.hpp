// Second level of the tangent method's terrain model (docs/detector.md, "Terrain
// refinement"): where the four planes of the cross partition do not explain the ground
// (rolling terrain, an embankment, a bank, a bowl, a crest, a ramp), square cells of the
// fitting grid get a surface of their own, grown outwards from the cell under the sensor.
// Each cell corrects the surface of the neighbour it was reached from by a small
// regularised least-squares fit on its eq. 3 inliers; a cell whose surface stays within a
// tolerance of its level-1 segment plane keeps that plane (and the paper's labels).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "hypotheses.hpp"
#include "labelling.hpp"
#include "plane_checks.hpp"
#include "scoring.hpp"

namespace vlpground::detail {

/// A non-vertical plane z = c + gx x + gy y (vehicle frame).
struct HeightPlane {
  float c = 0, gx = 0, gy = 0;
  [[nodiscard]] float at(float x, float y) const { return c + gx * x + gy * y; }
  static HeightPlane from(const Plane& p);
};

struct CellParams {
  int bins = 80;       // B of the fitting grid
  float bin_m = 1.f;   // bin side
  float x_lo = -40.f;  // grid corner (vehicle frame)
  float y_lo = -40.f;
  int cell_bins = 4;      // cell side in bins
  float eps = 0.2f;       // eq. 3 distance of the fit
  float sin_delta = 0.f;  // eq. 3 angle of the fit (reference surface's normal)
  // A cell's candidates are looked for this far under / over its reference surface.
  float window_down_m = 0.8f, window_up_m = 0.5f;
  // Bounds of a cell's correction of its reference (checks scale with cell size):
  // |offset at the cell centre| <= offset_m + offset_per_m * cell side,
  // |gradient change| <= gradient_change, and at most max_gradient overall.
  float offset_m = 0.1f, offset_per_m = 0.1f, gradient_change = 0.35f, max_gradient = 0.62f;
  float search_gradient_change = 0.5f;  // the same bound for the in-cell hypothesis search
  int min_points = 8;
  float keep_m = 0.1f;  // a fit this close to the level-1 plane at every corner keeps it
  float label_up_m = 0.18f, label_down_m = 0.5f;  // the level-1 label band
  // The surface under the sensor: min..max under it, found among the returns within
  // near_m when the level-1 plane explains less than half of them (embankments).
  float sensor_x = 0, sensor_y = 0, sensor_z = 0;
  float min_sensor_height_m = 0.5f, max_sensor_height_m = 5.f;
  float near_m = 10.f;
  // Cells nearer than this to the sensor (under the steepest ring) have no ground returns:
  // they take the vehicle's surface.
  float blind_m = 7.f;
  float min_nz = 0.978f;  // cos(max tilt) of the plane under the sensor
  std::uint64_t seed = 1;
};

enum class CellState : std::uint8_t { unvisited, level1, refined, inherited };

/// Whether a cell in `state` has a surface fitted to ground of its own (a level-1 plane that
/// explains it, or a refined fit), not one inherited from a neighbour.
[[nodiscard]] inline bool has_own_ground(CellState state) {
  return state == CellState::level1 || state == CellState::refined;
}

/// Where the level-2 surface has ground of its own, by cloud point; looked up only for the
/// few returns that need it, so nothing is computed per return. Default: nowhere.
struct Level2Coverage {
  const std::int32_t* point_bin = nullptr;    // fitting bin per cloud point (-1: none)
  const std::int32_t* cell_of_bin = nullptr;  // cell per fitting bin
  const CellState* cell_state = nullptr;      // state per cell
  [[nodiscard]] bool measured(std::size_t point) const {
    return point_bin != nullptr && point_bin[point] >= 0 &&
           has_own_ground(cell_state[cell_of_bin[point_bin[point]]]);
  }
};

/// A ring's inliers of a cell's fit, summed up: mean horizontal range from the sensor and
/// mean height over the cell's reference surface.
struct RingLine {
  float range_m = 0.f;
  float over_reference_m = 0.f;
};

/// Whether a fit that only two rings support, `nearer` and `farther` (by range), climbed a
/// ring line on an object past level ground rather than following a bend: the reference
/// is level (gradient under kLevelReference), the nearer ring lies on it (within
/// kNearOnReference_m), the farther one stands more than kLineOverNear_m over the nearer
/// one and more than kLineBeyond_m farther, and the fit turns the reference's gradient by more
/// than kLineTurn. A fence or a barrier met by one ring past the ground met by the ring below
/// (fences_s704: ring 5 on the ground 22 m out, ring 6 on a fence 0.55-0.65 m up at 24-26 m).
/// Terrain bending up far out bends from a gradient of its own (hills: 100 of 105 such
/// two-ring bends on a reference rising 0.03 or more).
[[nodiscard]] bool climbs_object_line(const HeightPlane& reference, const HeightPlane& fit,
                                      const RingLine& nearer, const RingLine& farther);

/// Histogram search of the densest window: the lowest window of `width` consecutive bins
/// whose count reaches `share` of the largest window count (share 1: the first densest).
/// Returns its first bin, or -1 when no window has `min_count`.
int densest_window(const std::uint16_t* hist, int bins, int width, float share, int min_count);
/// Plain form of densest_window (every window summed from scratch), for tests.
int densest_window_reference(const std::uint16_t* hist, int bins, int width, float share,
                             int min_count);

class TerrainCells {
 public:
  /// Builds every cell's surface from the level-1 segment planes `level1`. bin_slot maps
  /// bins to candidate slots (-1: empty).
  void fit(const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
           const SegmentPlanes& level1, const CellParams& params);

  /// Relabels the returns of cells whose surface is not their level-1 plane (same label
  /// rule as label_points; near a cell edge the neighbour's surface may accept too).
  void relabel(const Cloud& cloud, const PointFacts& facts, const LabelRule& rule,
               std::vector<std::uint8_t>& ground, std::vector<float>& height) const;

  [[nodiscard]] int cells_per_side() const { return side_; }
  [[nodiscard]] CellState state(int cell) const { return state_[static_cast<std::size_t>(cell)]; }
  [[nodiscard]] const HeightPlane& surface(int cell) const {
    return surface_[static_cast<std::size_t>(cell)];
  }
  /// Cells whose surface replaces the level-1 plane in labels.
  [[nodiscard]] int replaced_cells() const { return replaced_; }
  /// True when fitting bin `bin` (row * bins + col) lies in a cell whose surface replaces
  /// the level-1 plane.
  [[nodiscard]] bool replaced_bin(int bin) const {
    return replace_[static_cast<std::size_t>(cell_of_bin_[static_cast<std::size_t>(bin)])] != 0;
  }
  /// The coverage of the current fit for returns binned as `point_bin` (valid until the
  /// next fit).
  [[nodiscard]] Level2Coverage coverage(const std::int32_t* point_bin) const {
    return {point_bin, cell_of_bin_.data(), state_.data()};
  }
  /// The surface of the cell under the sensor (valid once a fit replaced a cell).
  [[nodiscard]] const HeightPlane& vehicle_surface() const { return surface_[vehicle_cell_]; }

 private:
  struct Fit;
  HeightPlane vehicle_seed(const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
                           const Plane& level1);
  [[nodiscard]] int near_score(const Plane& p) const;
  void fit_near_inliers(const Plane& p, PlaneFit& fit) const;
  [[nodiscard]] bool plausible_under_sensor(const Plane& p) const;
  [[nodiscard]] bool at_mounting_height(const Plane& p) const;
  bool fit_cell(int cell, const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
                const HeightPlane& ref, float border_x, float border_y, HeightPlane& out);
  bool fit_layer(int cell, const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
                 const HeightPlane& ref, HeightPlane& out);
  void gather_layer(const Fit& f, const Candidates& cand,
                    const std::vector<std::int32_t>& bin_slot, const HeightPlane& ref);
  bool search_cell(int cell, const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
                   const HeightPlane& ref, HeightPlane& out);
  [[nodiscard]] bool climbs_two_ring_line(const Candidates& cand, const Plane& best,
                                          const HeightPlane& ref, const HeightPlane& fit) const;
  void count_candidates(const Candidates& cand, const std::vector<std::int32_t>& bin_slot);
  [[nodiscard]] bool close(int cell, const HeightPlane& a, const HeightPlane& b) const;
  void explained_segments(const Candidates& cand, const std::vector<std::int32_t>& bin_slot,
                          const SegmentPlanes& level1);
  [[nodiscard]] int cell_of(float x, float y) const;
  [[nodiscard]] bool near_vehicle(int cell) const;

  CellParams p_;
  int side_ = 0, replaced_ = 0;
  std::size_t vehicle_cell_ = 0;
  std::vector<HeightPlane> surface_;
  std::vector<CellState> state_;
  std::vector<std::uint8_t> replace_;
  // The cell of every bin (row-major), made when the grid changes: no division per return.
  std::vector<std::int32_t> cell_of_bin_;
  std::vector<std::int32_t> cell_candidates_;  // per cell: its scoring candidates
  int table_bins_ = 0, table_cell_bins_ = 0;
  std::vector<std::array<float, 3>> normal_;  // per cell: unit normal of its surface
  bool segment_explained_[4] = {false, false, false, false};
  // Scoring candidates around the sensor with a tangent, gathered for the seed's search.
  struct NearPoints {
    std::vector<float> x, y, z, tx, ty, tz;
    void clear() {
      for (auto* v : {&x, &y, &z, &tx, &ty, &tz}) v->clear();
    }
    void push(const Candidates& c, std::size_t i) {
      x.push_back(c.x[i]);
      y.push_back(c.y[i]);
      z.push_back(c.z[i]);
      tx.push_back(c.tx[i]);
      ty.push_back(c.ty[i]);
      tz.push_back(c.tz[i]);
    }
  };
  NearPoints near_pts_;
  std::vector<std::int32_t> queue_, cell_pts_;
  // fit_layer: a cell's candidates with a usable tangent, gathered once per fit: offsets
  // u, v from the cell centre and residuals r over the reference; n of them.
  struct LayerPoints {
    std::vector<float> u, v, r;
    std::vector<std::uint8_t> ring;
    std::size_t n = 0;
  };
  LayerPoints layer_;
};

}  // namespace vlpground::detail
