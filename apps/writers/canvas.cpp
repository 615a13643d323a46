#include "writers/canvas.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

// stb_easy_font: functions are static, so this translation unit owns its copy.
#include <stb/stb_easy_font.h>

namespace vlpground::cli {
namespace {

constexpr std::size_t kMaxTextBytes = 512;
constexpr std::size_t kVertexBytes = 16;  // x, y, z floats and an RGBA colour per vertex

}  // namespace

Canvas::Canvas(int width, int height)
    : width_(width),
      height_(height),
      pixels_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3),
      text_buffer_(kMaxTextBytes + 1),
      vertex_buffer_(kMaxTextBytes * 300) {}  // stb_easy_font: ~270 bytes per character

void Canvas::clear(const Rgb& colour) {
  for (std::size_t i = 0; i < pixels_.size(); i += 3) {
    std::memcpy(&pixels_[i], colour.data(), 3);
  }
}

Rgb Canvas::pixel(int x, int y) const {
  const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                  static_cast<std::size_t>(x)) * 3;
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void Canvas::set(int x, int y, const Rgb& colour) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                  static_cast<std::size_t>(x)) * 3;
  std::memcpy(&pixels_[i], colour.data(), 3);
}

void Canvas::fill(int x, int y, int width, int height, const Rgb& colour) {
  const int x0 = std::max(x, 0), x1 = std::min(x + width, width_);
  const int y0 = std::max(y, 0), y1 = std::min(y + height, height_);
  for (int row = y0; row < y1; ++row) {
    for (int col = x0; col < x1; ++col) set(col, row, colour);
  }
}

void Canvas::line(int x0, int y0, int x1, int y1, const Rgb& colour) {
  const int steps = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  if (steps == 0) {
    set(x0, y0, colour);
    return;
  }
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    set(static_cast<int>(std::lround(x0 + t * (x1 - x0))),
        static_cast<int>(std::lround(y0 + t * (y1 - y0))), colour);
  }
}

int Canvas::text(int x, int y, std::string_view text, const Rgb& colour, int scale) {
  const std::size_t length = std::min(text.size(), kMaxTextBytes);
  std::memcpy(text_buffer_.data(), text.data(), length);
  text_buffer_[length] = '\0';
  const int quads = stb_easy_font_print(0, 0, text_buffer_.data(), nullptr, vertex_buffer_.data(),
                                        static_cast<int>(vertex_buffer_.size()));
  for (int q = 0; q < quads; ++q) {
    // A quad's first and third vertices are opposite corners of an axis-aligned rectangle.
    float first[2], third[2];
    std::memcpy(first, &vertex_buffer_[static_cast<std::size_t>(q * 4) * kVertexBytes], sizeof first);
    std::memcpy(third, &vertex_buffer_[static_cast<std::size_t>(q * 4 + 2) * kVertexBytes],
                sizeof third);
    const float s = static_cast<float>(scale);
    const int left = static_cast<int>(std::lround(std::min(first[0], third[0]) * s));
    const int top = static_cast<int>(std::lround(std::min(first[1], third[1]) * s));
    const int w = static_cast<int>(std::lround(std::fabs(third[0] - first[0]) * s));
    const int h = static_cast<int>(std::lround(std::fabs(third[1] - first[1]) * s));
    fill(x + left, y + top, std::max(w, 1), std::max(h, 1), colour);
  }
  return text_width(text, scale);
}

int Canvas::text_width(std::string_view text, int scale) {
  char buffer[kMaxTextBytes + 1];
  const std::size_t length = std::min(text.size(), kMaxTextBytes);
  std::memcpy(buffer, text.data(), length);
  buffer[length] = '\0';
  return stb_easy_font_width(buffer) * scale;
}

void Canvas::save_png(const std::string& path) const {
  if (stbi_write_png(path.c_str(), width_, height_, 3, pixels_.data(), width_ * 3) == 0) {
    throw std::runtime_error("cannot write " + path);
  }
}

}  // namespace vlpground::cli
