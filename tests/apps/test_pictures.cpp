// The PNG pictures: text is drawn where it is measured, every frame picture carries its
// header, legend and scale bar, and the run overview is written once at the end.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "writers/canvas.hpp"
#include "writers/png_writer.hpp"

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

using namespace vlpground;
using namespace vlpground::cli;

namespace {

constexpr Rgb kWhite = {255, 255, 255};

int count_pixels(const Canvas& c, int x0, int y0, int x1, int y1, const Rgb& colour) {
  int n = 0;
  for (int y = std::max(y0, 0); y < std::min(y1, c.height()); ++y) {
    for (int x = std::max(x0, 0); x < std::min(x1, c.width()); ++x) n += c.pixel(x, y) == colour;
  }
  return n;
}

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  explicit Image(const std::string& path) {
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
    REQUIRE(data != nullptr);
    rgb.assign(data, data + static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
    stbi_image_free(data);
  }
  [[nodiscard]] int count(int x0, int y0, int x1, int y1, const Rgb& colour) const {
    int n = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                               static_cast<std::size_t>(x)) * 3;
        n += rgb[i] == colour[0] && rgb[i + 1] == colour[1] && rgb[i + 2] == colour[2];
      }
    }
    return n;
  }
};

// A frame with a ring of returns 10 m around the sensor, half of them ground.
void ring_frame(Frame& frame, GroundResult& ground, std::uint64_t sequence) {
  frame.clear();
  frame.meta.sequence = sequence;
  frame.meta.first_time_ns = 1'700'000'000'000'000'000;
  frame.meta.rpm = 600;
  frame.meta.complete = true;
  ground.reserve(frame.stride());  // the result's rows as far apart as the frame's
  for (int c = 0; c < 360; ++c) {
    const int col = frame.append_column();
    const double a = c * 3.14159265358979 / 180.0;
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::size_t cell = frame.index(ring, col);
      frame.layer[0].valid[cell] = 1;
      frame.layer[0].x_m[cell] = static_cast<float>(10 * std::cos(a));
      frame.layer[0].y_m[cell] = static_cast<float>(10 * std::sin(a));
      ground.label[0][cell] = static_cast<std::uint8_t>(ring < 8 ? GroundLabel::ground
                                                                 : GroundLabel::obstacle);
    }
  }
  ground.columns = frame.columns();
  ground.ground_returns = 360 * 8;
  ground.obstacle_returns = 360 * 8;
}

}  // namespace

TEST_CASE("canvas: text lands inside its measured box and differs by content", "[pictures]") {
  Canvas canvas(200, 40);
  const int width = canvas.text(10, 5, "frame 42", kWhite, 2);
  CHECK(width == Canvas::text_width("frame 42", 2));
  const int inside = count_pixels(canvas, 10, 5, 10 + width, 5 + Canvas::line_height(2), kWhite);
  CHECK(inside > 50);
  CHECK(count_pixels(canvas, 0, 0, 200, 40, kWhite) == inside);  // nothing outside the box

  Canvas one(40, 20), seven(40, 20);
  one.text(0, 0, "1", kWhite);
  seven.text(0, 0, "7", kWhite);
  int differing = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 40; ++x) differing += one.pixel(x, y) != seven.pixel(x, y);
  }
  CHECK(differing > 3);
}

TEST_CASE("png writer: header, legend, scale bar per frame, and one overview per run",
          "[pictures]") {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("vlpground_pictures_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  Frame frame(512);
  GroundResult ground;
  {
    PngWriter named(dir.string(), 40.0, "front_left");
    for (std::uint64_t s = 0; s < 3; ++s) {
      ring_frame(frame, ground, s);
      named.write(frame, ground, 1.5);
    }
    CHECK_FALSE(std::filesystem::exists(dir / "overview.png"));
    named.finish();
    CHECK(std::filesystem::exists(dir / "overview.png"));
  }
  const Image picture((dir / "frame_000002.png").string());
  CHECK(picture.width == PngWriter::kWidth);
  CHECK(picture.height == PngWriter::kHeaderPixels + PngWriter::kWidth +
                              PngWriter::kCaptionPixels + kLasers * PngWriter::kRowPixels);
  const int header_text = picture.count(0, 0, picture.width, PngWriter::kHeaderPixels,
                                        Rgb{235, 235, 235});
  CHECK(header_text > 200);
  const int view_top = PngWriter::kHeaderPixels;
  // The legend's ground swatch (top right) and the scale bar (bottom left) are drawn.
  CHECK(picture.count(picture.width - 300, view_top, picture.width, view_top + 40,
                      Rgb{40, 200, 60}) >= 100);
  CHECK(picture.count(0, view_top + PngWriter::kWidth - 40, 300, view_top + PngWriter::kWidth,
                      Rgb{235, 235, 235}) > 100);
  // The ring of returns: ground and obstacles both appear in the view.
  CHECK(picture.count(0, view_top + 50, picture.width, view_top + PngWriter::kWidth - 50,
                      Rgb{230, 40, 40}) > 100);

  const Image overview((dir / "overview.png").string());
  CHECK(overview.width == 800);
  CHECK(overview.count(0, 60, 800, 250, Rgb{60, 220, 90}) > 20);   // ground share plot
  CHECK(overview.count(0, 260, 800, 460, Rgb{250, 190, 60}) > 20);  // detect time plot

  // The sensor name is part of the header: without it the header has fewer text pixels.
  const auto plain_dir = dir / "plain";
  {
    PngWriter plain(plain_dir.string(), 40.0);
    plain.write(frame, ground, 1.5);
  }
  const Image unnamed((plain_dir / "frame_000002.png").string());
  CHECK(unnamed.count(0, 0, unnamed.width, PngWriter::kHeaderPixels, Rgb{235, 235, 235}) <
        header_text);

  // Points are drawn in the vehicle frame: a sensor mounted 20 m ahead of the origin shows
  // its marker 200 pixels (0.1 m each) above the centre, and its ring of returns with it.
  const auto moved_dir = dir / "moved";
  {
    Extrinsics ahead;
    ahead.x_m = 20;
    PngWriter moved(moved_dir.string(), 40.0, "ahead", ahead);
    moved.write(frame, ground, 1.5);
  }
  const Image moved((moved_dir / "frame_000002.png").string());
  const Rgb sensor = {80, 160, 255};
  const int centre_y = PngWriter::kHeaderPixels + PngWriter::kWidth / 2;
  CHECK(moved.count(395, centre_y - 205, 405, centre_y - 195, sensor) >= 5);
  CHECK(moved.count(395, centre_y - 5, 405, centre_y + 5, sensor) == 0);
  std::filesystem::remove_all(dir);
}
