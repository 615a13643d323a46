// Fixed-size latency histogram: 10 us bins up to 500 ms plus an overflow bin. Recording never
// allocates; percentiles are exact to one bin.
//
// Thread-safety: none; the pipeline guards it with its stats mutex.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "vlpground/pipeline.hpp"

namespace vlpground::detail {

class LatencyHistogram {
 public:
  static constexpr double kBinMs = 0.01;
  static constexpr std::size_t kBins = 50'000;  // 500 ms

  void record(double ms) {
    const double clamped = std::max(ms, 0.0);
    const auto bin = static_cast<std::size_t>(clamped / kBinMs);
    ++counts_[std::min(bin, kBins)];
    ++samples_;
    sum_ms_ += clamped;
    max_ms_ = std::max(max_ms_, clamped);
  }

  [[nodiscard]] LatencyStats summary() const {
    LatencyStats s;
    s.samples = samples_;
    if (samples_ == 0) return s;
    s.p50_ms = percentile(0.50);
    s.p99_ms = percentile(0.99);
    s.max_ms = max_ms_;
    s.mean_ms = sum_ms_ / static_cast<double>(samples_);
    return s;
  }

 private:
  // Upper edge of the bin holding the q-quantile sample (never above the true maximum).
  [[nodiscard]] double percentile(double q) const {
    const auto rank = static_cast<std::uint64_t>(q * static_cast<double>(samples_ - 1)) + 1;
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b <= kBins; ++b) {
      seen += counts_[b];
      if (seen >= rank) {
        return std::min(static_cast<double>(b + 1) * kBinMs, max_ms_);
      }
    }
    return max_ms_;
  }

  std::array<std::uint32_t, kBins + 1> counts_{};
  std::uint64_t samples_ = 0;
  double sum_ms_ = 0;
  double max_ms_ = 0;
};

}  // namespace vlpground::detail
