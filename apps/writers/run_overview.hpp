// The run at a glance: ground share and detector time per frame as two small plots in one
// PNG (x = frame sequence number, so dropped frames show as gaps). Frames are bucketed per
// pixel column (the span min..max drawn faint, the mean bright), so an hour-long run stays
// readable.
//
// Thread-safety: one thread at a time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vlpground::cli {

class RunOverview {
 public:
  RunOverview() { samples_.reserve(4096); }

  /// `detect_ms` < 0: unknown (not plotted).
  void add(std::uint64_t sequence, std::uint64_t ground_returns, std::uint64_t labelled_returns,
           double detect_ms);
  [[nodiscard]] bool empty() const { return samples_.empty(); }
  [[nodiscard]] std::size_t size() const { return samples_.size(); }

  /// Draws the plots; `sensor_name` goes into the title. Throws std::runtime_error.
  void write_png(const std::string& path, const std::string& sensor_name) const;

 private:
  struct Sample {
    std::uint64_t sequence;
    float ground_percent;
    float detect_ms;
  };
  std::vector<Sample> samples_;
};

}  // namespace vlpground::cli
