#include "writers/run_overview.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "writers/canvas.hpp"

namespace vlpground::cli {
namespace {

constexpr int kWidth = 800, kHeight = 490;
constexpr int kLeft = 64, kRight = 16;  // plot area margins (axis labels on the left)
constexpr int kPlotHeight = 160;
constexpr Rgb kBackground = {18, 18, 22};
constexpr Rgb kAxis = {150, 150, 150};
constexpr Rgb kGrid = {50, 50, 58};
constexpr Rgb kText = {235, 235, 235};
constexpr Rgb kDimText = {170, 170, 170};
constexpr Rgb kGroundMean = {60, 220, 90};
constexpr Rgb kGroundSpan = {30, 90, 45};
constexpr Rgb kDetectMean = {250, 190, 60};
constexpr Rgb kDetectSpan = {100, 80, 35};

/// A round axis maximum at or above `value` (1, 2, 2.5, 5 x 10^k).
double nice_ceiling(double value) {
  if (!(value > 0)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (const double step : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (step * decade >= value) return step * decade;
  }
  return 10.0 * decade;
}

double percentile(std::vector<float> values, double p) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

struct Plot {
  Canvas& canvas;
  int top;
  double y_max;
  const char* unit;

  [[nodiscard]] int y_of(double value) const {
    const double clamped = std::clamp(value / y_max, 0.0, 1.0);
    return top + kPlotHeight - static_cast<int>(std::lround(clamped * kPlotHeight));
  }

  void axes(const char* title) const {
    canvas.text(kLeft, top - 16, title, kText);
    for (int i = 0; i <= 4; ++i) {
      const double value = y_max * i / 4.0;
      const int y = y_of(value);
      canvas.line(kLeft, y, kWidth - kRight, y, i == 0 ? kAxis : kGrid);
      char label[24];
      std::snprintf(label, sizeof label, "%g %s", value, unit);
      canvas.text(kLeft - 6 - Canvas::text_width(label), y - 4, label, kDimText);
    }
    canvas.line(kLeft, top, kLeft, top + kPlotHeight, kAxis);
  }
};

}  // namespace

void RunOverview::add(std::uint64_t sequence, std::uint64_t ground_returns,
                      std::uint64_t labelled_returns, double detect_ms) {
  const double share = labelled_returns == 0 ? 0.0
                                             : 100.0 * static_cast<double>(ground_returns) /
                                                   static_cast<double>(labelled_returns);
  samples_.push_back({sequence, static_cast<float>(share), static_cast<float>(detect_ms)});
}

void RunOverview::write_png(const std::string& path, const std::string& sensor_name) const {
  Canvas canvas(kWidth, kHeight);
  canvas.clear(kBackground);
  std::vector<float> shares, detects;
  for (const Sample& s : samples_) {
    shares.push_back(s.ground_percent);
    if (s.detect_ms >= 0) detects.push_back(s.detect_ms);
  }
  double share_sum = 0;
  for (const float s : shares) share_sum += s;
  const double detect_max = detects.empty() ? 0.0 : *std::max_element(detects.begin(), detects.end());

  char title[200];
  std::snprintf(title, sizeof title, "%s%srun overview: %zu frames", sensor_name.c_str(),
                sensor_name.empty() ? "" : " ", samples_.size());
  canvas.text(8, 6, title, kText, 2);
  char summary[200];
  std::snprintf(summary, sizeof summary,
                "ground share mean %.1f%%, min %.1f%%;  detect p50 %.2f ms, p99 %.2f ms, max %.2f ms",
                share_sum / static_cast<double>(shares.size()),
                static_cast<double>(*std::min_element(shares.begin(), shares.end())),
                percentile(detects, 0.5), percentile(detects, 0.99), detect_max);
  canvas.text(8, 30, summary, kDimText);

  const Plot share_plot{canvas, 70, 100.0, "%"};
  const Plot detect_plot{canvas, 70 + kPlotHeight + 50, nice_ceiling(detect_max), "ms"};
  share_plot.axes("ground share of labelled returns per frame");
  detect_plot.axes("detector time per frame");

  const std::uint64_t first = samples_.front().sequence, last = samples_.back().sequence;
  const double span = static_cast<double>(std::max<std::uint64_t>(last - first, 1));
  const int plot_width = kWidth - kLeft - kRight;
  auto x_of = [&](std::uint64_t sequence) {
    return kLeft + static_cast<int>(std::lround(static_cast<double>(sequence - first) / span *
                                                (plot_width - 1)));
  };
  // Per pixel column: min..max faint, mean bright, means joined while no frame is missing
  // in between; a marker per frame while they are few.
  struct Bucket {
    double lo = std::numeric_limits<double>::max(), hi = -1, sum = 0;
    int count = 0;
    std::uint64_t first = 0, last = 0;  // sequence numbers
  };
  const bool markers = samples_.size() * 6 <= static_cast<std::size_t>(kWidth - kLeft - kRight);
  auto draw = [&](const Plot& plot, auto value_of, const Rgb& span_colour, const Rgb& mean_colour) {
    std::vector<Bucket> buckets(static_cast<std::size_t>(plot_width));
    for (const Sample& s : samples_) {
      const double v = value_of(s);
      if (v < 0) continue;
      Bucket& b = buckets[static_cast<std::size_t>(x_of(s.sequence) - kLeft)];
      b.lo = std::min(b.lo, v);
      b.hi = std::max(b.hi, v);
      b.sum += v;
      if (b.count++ == 0) b.first = s.sequence;
      b.last = s.sequence;
    }
    const Bucket* previous = nullptr;
    int previous_x = 0, previous_y = 0;
    for (int i = 0; i < plot_width; ++i) {
      const Bucket& b = buckets[static_cast<std::size_t>(i)];
      if (b.count == 0) continue;
      const int x = kLeft + i;
      canvas.line(x, plot.y_of(b.lo), x, plot.y_of(b.hi), span_colour);
      const int y = plot.y_of(b.sum / b.count);
      if (previous != nullptr && b.first == previous->last + 1) {
        canvas.line(previous_x, previous_y, x, y, mean_colour);
      }
      if (markers) canvas.fill(x - 2, y - 2, 5, 5, mean_colour);
      canvas.set(x, y, mean_colour);
      previous = &b;
      previous_x = x;
      previous_y = y;
    }
  };
  draw(share_plot, [](const Sample& s) { return static_cast<double>(s.ground_percent); },
       kGroundSpan, kGroundMean);
  draw(detect_plot, [](const Sample& s) { return static_cast<double>(s.detect_ms); },
       kDetectSpan, kDetectMean);

  const int axis_y = detect_plot.top + kPlotHeight + 6;
  for (int i = 0; i <= 4; ++i) {
    const auto sequence = first + static_cast<std::uint64_t>(std::llround(span * i / 4.0));
    char label[32];
    std::snprintf(label, sizeof label, "%llu", static_cast<unsigned long long>(sequence));
    const int x = x_of(std::min(sequence, last));
    canvas.line(x, axis_y - 4, x, axis_y - 1, kAxis);
    canvas.text(x - Canvas::text_width(label) / 2, axis_y + 2, label, kDimText);
  }
  canvas.text(kLeft + plot_width / 2 - 90, axis_y + 18,
              "frame number (gaps: frames dropped or not delivered)", kDimText);
  canvas.save_png(path);
}

}  // namespace vlpground::cli
