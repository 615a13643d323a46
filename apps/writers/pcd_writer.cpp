#include "writers/pcd_writer.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "writers/label_access.hpp"

namespace vlpground::cli {
namespace {

constexpr std::size_t kPointBytes = 4 * 4 + 2 + 4 + 4;  // x y z intensity | ring | time | label

template <class T>
char* put(char* p, T v) {
  std::memcpy(p, &v, sizeof v);  // PCD binary is host (little-endian) order
  return p + sizeof v;
}

}  // namespace

PcdWriter::PcdWriter(const std::string& dir) : dir_(dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error("cannot create directory " + dir + ": " + ec.message());
  }
  points_.resize(static_cast<std::size_t>(2 * kLasers * kDefaultFrameCapacity) * kPointBytes);
}

void PcdWriter::write(const Frame& frame, const GroundResult& ground) {
  const std::size_t needed =
      static_cast<std::size_t>(frame.layers() * kLasers * frame.capacity()) * kPointBytes;
  if (points_.size() < needed) points_.resize(needed);
  char* p = points_.data();
  std::size_t count = 0;
  for (int col = 0; col < frame.columns(); ++col) {
    const std::int64_t column_ns = frame.column_time_ns[static_cast<std::size_t>(col)];
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::size_t cell = frame.index(ring, col);
      const int laser = frame.laser_of_ring[ring];
      const double time_s =
          static_cast<double>(column_ns + laser * kFiringIntervalNs - frame.meta.first_time_ns) *
          1e-9;
      for (int l = 0; l < frame.layers(); ++l) {
        const ReturnLayer& layer = frame.layer[l];
        if (layer.valid[cell] == 0) continue;
        p = put(p, layer.x_m[cell]);
        p = put(p, layer.y_m[cell]);
        p = put(p, layer.z_m[cell]);
        p = put(p, static_cast<float>(layer.intensity[cell]));
        p = put(p, static_cast<std::uint16_t>(ring));
        p = put(p, static_cast<float>(time_s));
        p = put(p, static_cast<std::uint32_t>(label_of(ground, l, ring, col)));
        ++count;
      }
    }
  }
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.pcd",
                static_cast<unsigned long long>(frame.meta.sequence));
  const std::string path = dir_ + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
  std::fprintf(f,
               "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
               "FIELDS x y z intensity ring time label\nSIZE 4 4 4 4 2 4 4\n"
               "TYPE F F F F U F U\nCOUNT 1 1 1 1 1 1 1\nWIDTH %zu\nHEIGHT 1\n"
               "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %zu\nDATA binary\n",
               count, count);
  const std::size_t bytes = count * kPointBytes;
  const bool ok = std::fwrite(points_.data(), 1, bytes, f) == bytes;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path);
}

}  // namespace vlpground::cli
