#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "allocation_counter.hpp"
#include "labelled_frame.hpp"
#include "vlpground/outputs/pointcloud2.hpp"

using namespace vlpground;
using outputs::CloudKind;

namespace {

// Reads one field of record `index` the way a PointCloud2 consumer does (by offset).
template <typename T>
T field(const std::vector<std::uint8_t>& data, std::size_t index, std::uint32_t offset) {
  T v;
  std::memcpy(&v, data.data() + index * outputs::kPointStep + offset, sizeof v);
  return v;
}

struct Decoded {
  float x, y, z, intensity, time;
  std::uint16_t ring;
  std::uint8_t label, ret;
};

Decoded record(const std::vector<std::uint8_t>& data, std::size_t i) {
  return {field<float>(data, i, 0),          field<float>(data, i, 4),
          field<float>(data, i, 8),          field<float>(data, i, 12),
          field<float>(data, i, 20),         field<std::uint16_t>(data, i, 16),
          field<std::uint8_t>(data, i, 18),  field<std::uint8_t>(data, i, 19)};
}

}  // namespace

TEST_CASE("PointCloud2 fields: names, types and offsets of the documented record") {
  const auto& f = outputs::kPointFields;
  const char* names[] = {"x", "y", "z", "intensity", "ring", "time", "label", "return"};
  const std::uint32_t offsets[] = {0, 4, 8, 12, 16, 20, 18, 19};
  const int types[] = {7, 7, 7, 7, 4, 7, 2, 2};  // FLOAT32 7, UINT16 4, UINT8 2
  for (std::size_t i = 0; i < f.size(); ++i) {
    CHECK(f[i].name == names[i]);
    CHECK(f[i].offset == offsets[i]);
    CHECK(static_cast<int>(f[i].datatype) == types[i]);
    CHECK(f[i].count == 1);
  }
  CHECK(outputs::kPointStep == 24);
}

TEST_CASE("Organized cloud: 16 rows by ring, one column per firing, NaN where no return") {
  const std::int64_t t0 = 1'700'000'000'123'456'789;
  test::LabelledTestFrame in(7, ReturnMode::strongest, t0);
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame));
  const auto shape = outputs::encode_pointcloud2(in.frame, in.ground, CloudKind::organized, data);
  REQUIRE(shape.height == 16);
  REQUIRE(shape.width == 7);
  CHECK(shape.point_step == 24);
  CHECK(shape.row_step == 7 * 24);
  CHECK_FALSE(shape.is_dense);
  REQUIRE(shape.bytes() == 16 * 7 * 24);
  for (int r = 0; r < kLasers; ++r) {
    for (int c = 0; c < 7; ++c) {
      const auto p = record(data, static_cast<std::size_t>(r * 7 + c));
      INFO("ring " << r << " column " << c);
      CHECK(p.ring == r);
      CHECK(p.ret == 0);
      const double expected_time =
          static_cast<double>(c * kSequencePeriodNs + in.frame.laser_of_ring[r] * kFiringIntervalNs) * 1e-9;
      CHECK(p.time == Approx(expected_time).epsilon(1e-6));
      if ((r + c) % 5 == 0) {
        CHECK(std::isnan(p.x));
        CHECK(std::isnan(p.y));
        CHECK(std::isnan(p.z));
        CHECK(p.intensity == 0.f);
        CHECK(p.label == 0);
      } else {
        CHECK(p.x == static_cast<float>(c));
        CHECK(p.y == static_cast<float>(r));
        CHECK(p.z == -1.5f);
        CHECK(p.intensity == static_cast<float>(r * 10));
        CHECK(p.label == in.label(0, r, c));
      }
    }
  }
}

TEST_CASE("Dual mode: 32 rows, the last return below the strongest") {
  test::LabelledTestFrame in(5, ReturnMode::dual, 0);
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame));
  const auto shape = outputs::encode_pointcloud2(in.frame, in.ground, CloudKind::organized, data);
  REQUIRE(shape.height == 32);
  REQUIRE(shape.width == 5);
  const auto p = record(data, static_cast<std::size_t>((16 + 4) * 5 + 1));  // last, ring 4, col 1
  CHECK(p.ret == 1);
  CHECK(p.ring == 4);
  CHECK(p.x == 1.25f);
  CHECK(p.intensity == 41.f);
  CHECK(p.label == in.label(1, 4, 1));
}

TEST_CASE("Ground-only and obstacle-only clouds are dense and split the labelled returns") {
  test::LabelledTestFrame in(9, ReturnMode::dual, 0);
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame));
  std::size_t ground = 0, obstacle = 0;
  for (int l = 0; l < 2; ++l)
    for (int r = 0; r < kLasers; ++r)
      for (int c = 0; c < 9; ++c) {
        ground += in.label(l, r, c) == 1 ? 1u : 0u;
        obstacle += in.label(l, r, c) == 2 ? 1u : 0u;
      }
  REQUIRE(ground > 0);
  REQUIRE(obstacle > 0);
  for (const auto& [kind, wanted, count] :
       {std::tuple{CloudKind::ground_only, 1, ground}, std::tuple{CloudKind::obstacle_only, 2, obstacle}}) {
    const auto shape = outputs::encode_pointcloud2(in.frame, in.ground, kind, data);
    CHECK(shape.height == 1);
    CHECK(shape.width == count);
    CHECK(shape.row_step == count * 24);
    CHECK(shape.is_dense);
    for (std::size_t i = 0; i < count; ++i) {
      const auto p = record(data, i);
      CHECK(p.label == wanted);
      CHECK_FALSE(std::isnan(p.x));
    }
  }
}

TEST_CASE("A frame without labels encodes label 0 everywhere") {
  test::LabelledTestFrame in(4, ReturnMode::strongest, 0);
  const GroundResult empty;
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame));
  outputs::encode_pointcloud2(in.frame, empty, CloudKind::organized, data);
  for (std::size_t i = 0; i < 16 * 4; ++i) CHECK(record(data, i).label == 0);
  CHECK(outputs::encode_pointcloud2(in.frame, empty, CloudKind::ground_only, data).width == 0);
}

TEST_CASE("Too small a buffer is refused with the size needed") {
  test::LabelledTestFrame in(4, ReturnMode::strongest, 0);
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame) - 1);
  CHECK_THROWS_WITH(outputs::encode_pointcloud2(in.frame, in.ground, CloudKind::organized, data),
                    Catch::Contains("needs 1536"));
}

TEST_CASE("Encoding allocates nothing") {
  if (test::allocation_count() < 0) {
    WARN("skipped: allocations are not counted under AddressSanitizer");
    return;
  }
  test::LabelledTestFrame in(64, ReturnMode::dual, 0);
  std::vector<std::uint8_t> data(outputs::max_cloud_bytes(in.frame));
  const long before = test::allocation_count();
  for (int k = 0; k < 10; ++k) {
    for (auto kind : {CloudKind::organized, CloudKind::ground_only, CloudKind::obstacle_only}) {
      outputs::encode_pointcloud2(in.frame, in.ground, kind, data);
    }
  }
  CHECK(test::allocation_count() == before);
}
