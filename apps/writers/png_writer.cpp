#include "writers/png_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <stdexcept>

#include "writers/label_access.hpp"

namespace vlpground::cli {
namespace {

constexpr Rgb kGround = {40, 200, 60};
constexpr Rgb kObstacle = {230, 40, 40};
constexpr Rgb kUnlabelled = {120, 120, 120};
constexpr Rgb kNoReturn = {15, 15, 15};
constexpr Rgb kCentre = {255, 255, 255};
constexpr Rgb kSegment = {240, 200, 40};
constexpr Rgb kSegmentNoGround = {90, 90, 200};
constexpr Rgb kSensor = {80, 160, 255};
constexpr Rgb kText = {235, 235, 235};
constexpr Rgb kDimText = {170, 170, 170};
constexpr Rgb kPanel = {30, 30, 36};

const Rgb& colour_of(GroundLabel label) {
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

/// "2026-11-30 12:00:01.234 UTC", or "time unknown" for a zero stamp.
std::string utc_text(std::int64_t ns) {
  if (ns <= 0) return "time unknown";
  const std::time_t seconds = static_cast<std::time_t>(ns / 1'000'000'000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[48];
  std::snprintf(text, sizeof text, "%04d-%02d-%02d %02d:%02d:%02d.%03d UTC", utc.tm_year + 1900,
                utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec,
                static_cast<int>((ns / 1'000'000) % 1000));
  return text;
}

/// The longest of 1, 2, 5 x 10^k metres not above `limit_m`.
double nice_length(double limit_m) {
  double best = 1.0;
  for (double decade = 1.0; decade <= limit_m; decade *= 10.0) {
    for (const double step : {1.0, 2.0, 5.0}) {
      if (step * decade <= limit_m) best = step * decade;
    }
  }
  return best;
}

}  // namespace

PngWriter::PngWriter(const std::string& dir, double view_radius_m, std::string sensor_name,
                     const Extrinsics& extrinsics)
    : dir_(dir),
      sensor_name_(std::move(sensor_name)),
      metres_per_pixel_(2.0 * view_radius_m / kWidth),
      to_vehicle_(vehicle_from_sensor(extrinsics)),
      canvas_(kWidth, kHeaderPixels + kWidth + kCaptionPixels + kLasers * kRowPixels) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error("cannot create directory " + dir + ": " + ec.message());
  }
}

PngWriter::~PngWriter() {
  try {
    finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground: %s\n", e.what());
  }
}

// Vehicle frame to picture: x forward is up, y left is left, the sensor in the middle.
void PngWriter::set_metres(double x_m, double y_m, const Rgb& colour) {
  const int px = static_cast<int>(kWidth / 2 - y_m / metres_per_pixel_);
  const int py = static_cast<int>(kWidth / 2 - x_m / metres_per_pixel_);
  if (py < 0 || py >= kWidth) return;  // keep the view out of the header and range image
  canvas_.set(px, kHeaderPixels + py, colour);
}

void PngWriter::line_metres(double x0_m, double y0_m, double x1_m, double y1_m,
                            const Rgb& colour) {
  const double steps = std::max(std::hypot(x1_m - x0_m, y1_m - y0_m) / metres_per_pixel_, 1.0);
  for (int s = 0; s <= static_cast<int>(steps); ++s) {
    const double t = s / steps;
    set_metres(x0_m + t * (x1_m - x0_m), y0_m + t * (y1_m - y0_m), colour);
  }
}

void PngWriter::draw_header(const Frame& frame, const GroundResult& ground, double detect_ms) {
  const FrameMeta& m = frame.meta;
  char title[160];
  std::snprintf(title, sizeof title, "%s%sframe %llu   %s", sensor_name_.c_str(),
                sensor_name_.empty() ? "" : "   ", static_cast<unsigned long long>(m.sequence),
                utc_text(m.first_time_ns).c_str());
  canvas_.text(6, 4, title, kText, 2);
  const std::uint64_t labelled = ground.ground_returns + ground.obstacle_returns;
  const double share = labelled == 0 ? 0.0 : 100.0 * static_cast<double>(ground.ground_returns) /
                                                  static_cast<double>(labelled);
  char detail[200];
  int n = std::snprintf(detail, sizeof detail,
                        "%.0f rpm, %s, %d columns, %s; ground %.1f%% of %llu returns",
                        m.rpm, m.mode == ReturnMode::dual ? "dual" : "single return",
                        frame.columns(), m.complete ? "complete" : "INCOMPLETE", share,
                        static_cast<unsigned long long>(labelled));
  if (detect_ms >= 0 && n > 0 && static_cast<std::size_t>(n) < sizeof detail) {
    std::snprintf(detail + n, sizeof detail - static_cast<std::size_t>(n), "; detect %.2f ms",
                  detect_ms);
  }
  canvas_.text(6, 28, detail, kDimText, 1);
}

void PngWriter::draw_birds_eye(const Frame& frame, const GroundResult& ground) {
  const RigidTransform& t = to_vehicle_;
  for (int l = 0; l < frame.layers(); ++l) {
    const ReturnLayer& layer = frame.layer[l];
    for (int ring = 0; ring < kLasers; ++ring) {
      for (int col = 0; col < frame.columns(); ++col) {
        const std::size_t cell = frame.index(ring, col);
        if (layer.valid[cell] == 0) continue;
        const float x = layer.x_m[cell], y = layer.y_m[cell], z = layer.z_m[cell];
        set_metres(t.r[0][0] * x + t.r[0][1] * y + t.r[0][2] * z + t.t[0],
                   t.r[1][0] * x + t.r[1][1] * y + t.r[1][2] * z + t.t[1],
                   colour_of(label_of(ground, l, ring, col)));
      }
    }
  }
  for (int d = -2; d <= 2; ++d) {  // the sensor where it is mounted
    set_metres(t.t[0] + d * metres_per_pixel_, t.t[1], kSensor);
    set_metres(t.t[0], t.t[1] + d * metres_per_pixel_, kSensor);
  }
}

void PngWriter::draw_partition(const GroundResult& ground) {
  const double r = metres_per_pixel_ * kWidth / 2;
  const double cx = ground.centre_x_m, cy = ground.centre_y_m;
  line_metres(cx, -r, cx, r, kCentre);  // the cross through the partition centre (paper, Fig. 2)
  line_metres(-r, cy, r, cy, kCentre);
  for (const GroundSegment& s : ground.segments) {
    if (s.x_max_m <= s.x_min_m || s.y_max_m <= s.y_min_m) continue;
    const Rgb& c = s.has_ground ? kSegment : kSegmentNoGround;
    line_metres(s.x_min_m, s.y_min_m, s.x_max_m, s.y_min_m, c);
    line_metres(s.x_min_m, s.y_max_m, s.x_max_m, s.y_max_m, c);
    line_metres(s.x_min_m, s.y_min_m, s.x_min_m, s.y_max_m, c);
    line_metres(s.x_max_m, s.y_min_m, s.x_max_m, s.y_max_m, c);
  }
}

void PngWriter::draw_legend() {
  struct Entry {
    const Rgb& colour;
    const char* text;
  };
  static const Entry kEntries[] = {
      {kGround, "ground"},
      {kObstacle, "obstacle"},
      {kSegment, "segment with its own ground plane"},
      {kSegmentNoGround, "segment without (plane inherited)"},
      {kCentre, "partition centre"},
      {kSensor, "sensor (vehicle frame, x forward = up)"},
  };
  constexpr int kSwatch = 10, kLine = 15, kPad = 6;
  int widest = 0;
  for (const Entry& e : kEntries) widest = std::max(widest, Canvas::text_width(e.text));
  const int width = kPad * 3 + kSwatch + widest;
  const int height = kPad * 2 + kLine * static_cast<int>(std::size(kEntries)) - (kLine - kSwatch);
  const int left = kWidth - width - 8, top = kHeaderPixels + 8;
  canvas_.fill(left, top, width, height, kPanel);
  for (std::size_t i = 0; i < std::size(kEntries); ++i) {
    const int y = top + kPad + static_cast<int>(i) * kLine;
    canvas_.fill(left + kPad, y, kSwatch, kSwatch, kEntries[i].colour);
    canvas_.text(left + 2 * kPad + kSwatch, y + 1, kEntries[i].text, kText);
  }
}

void PngWriter::draw_scale_bar() {
  const double length_m = nice_length(metres_per_pixel_ * kWidth / 4);
  const int length_px = static_cast<int>(std::lround(length_m / metres_per_pixel_));
  const int left = 16, baseline = kHeaderPixels + kWidth - 16;
  char label[32];
  std::snprintf(label, sizeof label, "%g m", length_m);
  canvas_.fill(left - 6, baseline - 26, length_px + 12, 32, kPanel);
  canvas_.fill(left, baseline - 2, length_px, 3, kText);
  canvas_.fill(left, baseline - 8, 2, 9, kText);
  canvas_.fill(left + length_px - 2, baseline - 8, 2, 9, kText);
  canvas_.text(left + (length_px - Canvas::text_width(label)) / 2, baseline - 22, label, kText);
}

void PngWriter::draw_range_image(const Frame& frame, const GroundResult& ground) {
  const int caption = kHeaderPixels + kWidth;
  canvas_.text(6, caption + 3,
               "range image: ring 15 (highest) at the top, columns in firing order from the cut",
               kDimText);
  const int top = caption + kCaptionPixels;
  const int columns = std::max(frame.columns(), 1);
  for (int px = 0; px < kWidth; ++px) {
    const int col = std::min(px * columns / kWidth, columns - 1);
    for (int ring = 0; ring < kLasers; ++ring) {
      const bool has = frame.columns() > 0 && frame.layer[0].valid[frame.index(ring, col)] != 0;
      const Rgb& c = has ? colour_of(label_of(ground, 0, ring, col)) : kNoReturn;
      canvas_.fill(px, top + (kLasers - 1 - ring) * kRowPixels, 1, kRowPixels, c);
    }
  }
}

void PngWriter::write(const Frame& frame, const GroundResult& ground, double detect_ms) {
  canvas_.clear();
  draw_header(frame, ground, detect_ms);
  draw_partition(ground);
  draw_birds_eye(frame, ground);
  draw_legend();
  draw_scale_bar();
  draw_range_image(frame, ground);
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.png",
                static_cast<unsigned long long>(frame.meta.sequence));
  canvas_.save_png(dir_ + "/" + name);
  overview_.add(frame.meta.sequence, ground.ground_returns,
                ground.ground_returns + ground.obstacle_returns, detect_ms);
}

void PngWriter::finish() {
  if (finished_) return;
  finished_ = true;
  if (overview_.empty()) return;
  overview_.write_png(dir_ + "/overview.png", sensor_name_);
}

}  // namespace vlpground::cli
