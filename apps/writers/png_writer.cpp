#include "writers/png_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "writers/label_access.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace vlpground::cli {
namespace {

constexpr std::uint8_t kGround[3] = {40, 200, 60};
constexpr std::uint8_t kObstacle[3] = {230, 40, 40};
constexpr std::uint8_t kUnlabelled[3] = {120, 120, 120};
constexpr std::uint8_t kNoReturn[3] = {15, 15, 15};
constexpr std::uint8_t kCentre[3] = {255, 255, 255};
constexpr std::uint8_t kSegment[3] = {240, 200, 40};
constexpr std::uint8_t kSegmentNoGround[3] = {90, 90, 200};
constexpr std::uint8_t kSensor[3] = {80, 160, 255};

const std::uint8_t (&colour_of(GroundLabel label))[3] {
  switch (label) {
    case GroundLabel::ground:
      return kGround;
    case GroundLabel::obstacle:
      return kObstacle;
    case GroundLabel::no_return:
      break;
  }
  return kUnlabelled;
}

}  // namespace

PngWriter::PngWriter(const std::string& dir, double view_radius_m)
    : dir_(dir),
      metres_per_pixel_(2.0 * view_radius_m / kWidth),
      height_(kWidth + 4 + kLasers * kRowPixels) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error("cannot create directory " + dir + ": " + ec.message());
  }
  pixels_.resize(static_cast<std::size_t>(kWidth * height_ * 3));
}

void PngWriter::set(int x, int y, const std::uint8_t (&rgb)[3]) {
  if (x < 0 || y < 0 || x >= kWidth || y >= height_) return;
  const auto i = static_cast<std::size_t>((y * kWidth + x) * 3);
  pixels_[i] = rgb[0];
  pixels_[i + 1] = rgb[1];
  pixels_[i + 2] = rgb[2];
}

// Vehicle frame to picture: x forward is up, y left is left, the sensor in the middle.
void PngWriter::line(double x0_m, double y0_m, double x1_m, double y1_m,
                     const std::uint8_t (&rgb)[3]) {
  const double steps = std::max(std::hypot(x1_m - x0_m, y1_m - y0_m) / metres_per_pixel_, 1.0);
  for (int s = 0; s <= static_cast<int>(steps); ++s) {
    const double t = s / steps;
    const double x = x0_m + t * (x1_m - x0_m), y = y0_m + t * (y1_m - y0_m);
    set(static_cast<int>(kWidth / 2 - y / metres_per_pixel_),
        static_cast<int>(kWidth / 2 - x / metres_per_pixel_), rgb);
  }
}

void PngWriter::draw_birds_eye(const Frame& frame, const GroundResult& ground) {
  for (int l = 0; l < frame.layers(); ++l) {
    const ReturnLayer& layer = frame.layer[l];
    for (int ring = 0; ring < kLasers; ++ring) {
      for (int col = 0; col < frame.columns(); ++col) {
        const std::size_t cell = frame.index(ring, col);
        if (layer.valid[cell] == 0) continue;
        const int px = static_cast<int>(kWidth / 2 - layer.y_m[cell] / metres_per_pixel_);
        const int py = static_cast<int>(kWidth / 2 - layer.x_m[cell] / metres_per_pixel_);
        if (py >= kWidth) continue;  // keep the bird's-eye view out of the range image
        set(px, py, colour_of(label_of(ground, l, ring, col)));
      }
    }
  }
  for (int d = -2; d <= 2; ++d) {
    set(kWidth / 2 + d, kWidth / 2, kSensor);
    set(kWidth / 2, kWidth / 2 + d, kSensor);
  }
}

void PngWriter::draw_partition(const GroundResult& ground) {
  const double r = metres_per_pixel_ * kWidth / 2;
  const double cx = ground.centre_x_m, cy = ground.centre_y_m;
  line(cx, -r, cx, r, kCentre);  // the cross through the partition centre (paper, Fig. 2)
  line(-r, cy, r, cy, kCentre);
  for (const GroundSegment& s : ground.segments) {
    if (s.x_max_m <= s.x_min_m || s.y_max_m <= s.y_min_m) continue;
    const auto& c = s.has_ground ? kSegment : kSegmentNoGround;
    line(s.x_min_m, s.y_min_m, s.x_max_m, s.y_min_m, c);
    line(s.x_min_m, s.y_max_m, s.x_max_m, s.y_max_m, c);
    line(s.x_min_m, s.y_min_m, s.x_min_m, s.y_max_m, c);
    line(s.x_max_m, s.y_min_m, s.x_max_m, s.y_max_m, c);
  }
}

void PngWriter::draw_range_image(const Frame& frame, const GroundResult& ground) {
  const int top = kWidth + 4;
  const int columns = std::max(frame.columns(), 1);
  for (int px = 0; px < kWidth; ++px) {
    const int col = std::min(px * columns / kWidth, columns - 1);
    for (int ring = 0; ring < kLasers; ++ring) {
      const bool has = frame.columns() > 0 && frame.layer[0].valid[frame.index(ring, col)] != 0;
      const auto& c = has ? colour_of(label_of(ground, 0, ring, col)) : kNoReturn;
      const int y0 = top + (kLasers - 1 - ring) * kRowPixels;  // highest ring on top
      for (int dy = 0; dy < kRowPixels; ++dy) set(px, y0 + dy, c);
    }
  }
}

void PngWriter::write(const Frame& frame, const GroundResult& ground) {
  std::fill(pixels_.begin(), pixels_.end(), std::uint8_t{0});
  draw_partition(ground);
  draw_birds_eye(frame, ground);
  draw_range_image(frame, ground);
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.png",
                static_cast<unsigned long long>(frame.meta.sequence));
  const std::string path = dir_ + "/" + name;
  if (stbi_write_png(path.c_str(), kWidth, height_, 3, pixels_.data(), kWidth * 3) == 0) {
    throw std::runtime_error("cannot write " + path);
  }
}

}  // namespace vlpground::cli
