// An RGB pixel buffer with the few drawing primitives the PNG pictures need: points, filled
// rectangles, lines and text (stb_easy_font's quads, drawn at an integer scale), saved with
// stb_image_write. Storage is allocated once; drawing never allocates.
//
// Thread-safety: one thread at a time.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace vlpground::cli {

using Rgb = std::array<std::uint8_t, 3>;

class Canvas {
 public:
  Canvas(int width, int height);

  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }

  void clear(const Rgb& colour = {0, 0, 0});
  /// The colour at (x, y), which must lie on the canvas.
  [[nodiscard]] Rgb pixel(int x, int y) const;
  /// Pixels outside the canvas are ignored by every primitive.
  void set(int x, int y, const Rgb& colour);
  void fill(int x, int y, int width, int height, const Rgb& colour);
  void line(int x0, int y0, int x1, int y1, const Rgb& colour);
  /// Draws `text` (ASCII, '\n' starts a line) with its top-left corner at (x, y); returns
  /// the width drawn in pixels. `scale` 1 gives glyphs about 7 pixels high.
  int text(int x, int y, std::string_view text, const Rgb& colour, int scale = 1);
  /// Width in pixels `text` would take (longest line).
  [[nodiscard]] static int text_width(std::string_view text, int scale = 1);
  /// Height of one line of text at `scale`, spacing included.
  [[nodiscard]] static int line_height(int scale = 1) { return 12 * scale; }

  /// Throws std::runtime_error when the file cannot be written.
  void save_png(const std::string& path) const;

 private:
  int width_, height_;
  std::vector<std::uint8_t> pixels_;
  std::vector<char> text_buffer_;     // NUL-terminated copy of the text for stb_easy_font
  std::vector<char> vertex_buffer_;  // quads from stb_easy_font
};

}  // namespace vlpground::cli
