// Steep flags (steep.hpp): faces across a ring that did not return in its column.
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "column_scan.hpp"
#include "steep.hpp"

using namespace column_scan;

namespace {

std::vector<std::uint8_t> steep_flags(const Cloud& cloud, bool faces_across_gaps) {
  std::vector<std::uint8_t> steep;
  mark_steep(cloud, steep);
  FaceTable table;
  if (faces_across_gaps) add_faces_across_gaps(cloud, table, steep);
  return steep;
}

// A return of the last layer of a deduplicated cloud (build_cloud's layout): a distinct last
// return gets a point of its own; a twin repeats the strongest echo, whose point stands in
// last_rows.
void add_last(Scan& s, int ring, int col, float r, float z) {
  add(s, ring, col, r, z, 2);
  s.cloud.layer.back() = 1;
  s.cloud.twin.push_back(0);
}

}  // namespace

TEST_CASE("steep flags: a face whose next ring did not return is a face from the ring beyond",
          "[detector][steep]") {
  Scan s;
  // Column 0, sim jam_s702_hires (frame 0, column 126): ring 0 on a dark car's side 6.7 m
  // out, 0.79 m up; ring 1 dropped out there; rings 2-3 on the same side.
  // Column 1, sim hills_s1805 (tilted): ring 0 on a hillside 38.1 m out, ring 1 through a
  // tree crown without a return, ring 2 on the trunk 1.1 m farther and 2.8 m higher: the
  // ground at a face's foot, no face.
  // Column 2: as column 0, but ring 1 returned, through a gap far behind the car: adjacent
  // rings decide, as everywhere (none of them is steep with ring 0).
  add(s, 0, 0, 6.68f, 0.79f, 2);
  add(s, 0, 1, 38.08f, 4.46f, 1);
  add(s, 0, 2, 6.68f, 0.79f, 2);
  add(s, 1, 2, 25.f, 0.5f, 2);
  add(s, 2, 0, 6.67f, 1.11f, 2);
  add(s, 2, 1, 39.20f, 7.29f, 2);
  add(s, 2, 2, 6.67f, 1.11f, 2);
  add(s, 3, 0, 6.65f, 1.26f, 2);
  add(s, 3, 2, 6.65f, 1.26f, 2);
  s.cloud.twin.assign(s.cloud.size(), 0);
  const auto adjacent = steep_flags(s.cloud, false);
  const auto with_gaps = steep_flags(s.cloud, true);
  // Points in cloud order: ring 0 columns 0-2 (0-2), ring 1 column 2 (3), ring 2 columns
  // 0-2 (4-6), ring 3 columns 0 and 2 (7-8).
  CHECK(adjacent[0] == 0);
  CHECK(with_gaps[0] == 1);
  CHECK(with_gaps[4] == 1);
  CHECK(with_gaps[1] == 0);  // the hillside under the trunk
  CHECK(with_gaps[2] == 0);  // ring 1 returned in column 2
  CHECK(with_gaps[6] == 1);  // ring 2 and 3 on the car side, adjacent
}

TEST_CASE("steep flags: a distinct last return across a ring without a return",
          "[detector][steep]") {
  // Dual returns, deduplicated: ring 0's last echo in column 0 is distinct (a car side 6.69 m
  // out), ring 1 returned in neither layer, ring 2's last echo repeats its strongest one (a
  // twin, its strongest point standing in last_rows) on the same side.
  Scan s;
  add(s, 0, 0, 20.f, 0.1f, 1);   // 0: ring 0's strongest echo, through the car's edge
  add(s, 2, 0, 6.67f, 1.11f, 2);  // 1: ring 2, both layers
  s.cloud.twin.assign(s.cloud.size(), 0);
  Cloud& c = s.cloud;
  c.deduplicated = true;
  c.last_begin = c.size();
  add_last(s, 0, 0, 6.69f, 0.79f);  // 2: ring 0's distinct last echo
  c.twin[1] = 1;
  c.last_rows = {2, 1};  // ring 0: the distinct point; ring 2: the twin's strongest point
  const auto adjacent = steep_flags(c, false);
  const auto with_gaps = steep_flags(c, true);
  CHECK(adjacent[2] == 0);
  CHECK(with_gaps[2] == 1);
  CHECK(with_gaps[0] == 0);  // the strongest layer: ring 0 lies 13 m off ring 2's face
  CHECK(with_gaps[1] == 0);  // the twin keeps its strongest row's flag
}

TEST_CASE("column profiles: a car side's lowest return is no ground when its next ring dropped out",
          "[detector][profiles][steep]") {
  // Sim jam_s702_hires (frame 0, column 126): ring 0 on a car's side 6.7 m out, 0.79 m up,
  // ring 1 dropped out, rings 2-5 on the side, ring 6 onwards on a facade 14.3 m out; the
  // level-2 surface through ring 0. Not steep, ring 0 rises from the start within the walk's
  // allowance (0.25 m + 0.12 per m).
  const std::vector<ColumnReturn> car = {{0, 6.68f, 0.79f, 0.f},  {2, 6.67f, 1.11f, 1.11f},
                                         {3, 6.65f, 1.26f, 1.26f},  {4, 6.62f, 1.42f, 1.42f},
                                         {5, 7.07f, 1.55f, 1.55f},  {6, 14.34f, 1.46f, 1.46f},
                                         {7, 14.37f, 1.79f, 1.79f}, {8, 14.30f, 2.12f, 2.12f}};
  const std::vector<int> ground = label_column(car);
  for (const int g : ground) CHECK(g == 0);
}
