#include "cli/capture_probe.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "vlpground/types.hpp"

namespace vlpground::cli {
namespace {

constexpr std::size_t kStampOffset = 1200;
constexpr std::size_t kModeOffset = 1204;
constexpr std::size_t kProductOffset = 1205;
constexpr double kHourUs = 3'600'000'000.0;

std::uint32_t load_le32(const std::uint8_t* p) {
  std::uint8_t b[4];
  std::memcpy(b, p, 4);
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
}

template <class Map>
std::uint8_t most_common(const Map& m) {
  std::uint8_t best = 0;
  std::uint64_t n = 0;
  for (const auto& [k, v] : m) {
    if (v > n) best = k, n = v;
  }
  return best;
}

}  // namespace

std::uint8_t CaptureProbe::main_product() const { return most_common(product_bytes); }
std::uint8_t CaptureProbe::main_mode() const { return most_common(mode_bytes); }

bool CaptureProbe::timing_is_vlp16() const {
  if (median_spacing_us <= 0) return true;  // a single packet: nothing to contradict
  const double expected_us = main_mode() == kModeDual ? 663.552 : 1327.104;
  return std::fabs(median_spacing_us - expected_us) < 0.05 * expected_us;
}

std::string CaptureProbe::family() const {
  if (data_packets == 0) return "unknown";
  const std::uint8_t product = main_product();
  if (product == kProductHiRes) return "Puck Hi-Res";
  if (product == kProductVlp16) return timing_is_vlp16() ? "VLP-16" : "unknown";
  if (product == 0x21) return timing_is_vlp16() && median_spacing_us > 0 ? "VLP-16" : "HDL-32E";
  if (product == 0x28) return "VLP-32C";
  return timing_is_vlp16() && median_spacing_us > 0 ? "VLP-16" : "unknown";
}

bool CaptureProbe::is_vlp16() const {
  const std::string f = family();
  return f == "VLP-16" || f == "Puck Hi-Res";
}

std::string CaptureProbe::verdict() const {
  char line[256];
  if (data_packets == 0) {
    std::snprintf(line, sizeof line,
                  "found no 1206-byte data packets: %llu records, %llu position packets, "
                  "%llu other",
                  static_cast<unsigned long long>(counters.records),
                  static_cast<unsigned long long>(counters.position_packets),
                  static_cast<unsigned long long>(counters.skipped()));
    return line;
  }
  std::snprintf(line, sizeof line, "found %s data: product byte 0x%02x, %.0f us packet spacing",
                family().c_str(), main_product(), median_spacing_us);
  return line;
}

CaptureProbe probe_capture(const PcapSourceConfig& config, std::uint64_t max_data_packets) {
  CaptureProbe probe;
  std::vector<double> spacing;
  try {
    PcapSourceConfig c = config;
    c.loop = false;
    c.rate = 0;
    auto source = open_pcap_source(c);
    PacketView view;
    double previous_us = -1;
    while (max_data_packets == 0 || probe.data_packets < max_data_packets) {
      const SourceStatus s = source->next(view, 1000);
      if (s != SourceStatus::packet) break;
      if (view.kind != PacketKind::data || view.bytes.size() < kProductOffset + 1) continue;
      ++probe.data_packets;
      ++probe.product_bytes[view.bytes[kProductOffset]];
      ++probe.mode_bytes[view.bytes[kModeOffset]];
      const double us = load_le32(view.bytes.data() + kStampOffset);
      if (previous_us >= 0) {
        double d = us - previous_us;
        if (d < -kHourUs / 2) d += kHourUs;  // hour wrap
        if (d > 0) spacing.push_back(d);
      }
      if (probe.first_stamp_s < 0) probe.first_stamp_s = us * 1e-6;
      probe.last_stamp_s = us * 1e-6;
      previous_us = us;
    }
    probe.counters = source->counters();
  } catch (const std::exception& e) {
    probe.error = e.what();
    return probe;
  }
  if (!spacing.empty()) {
    const auto mid = spacing.begin() + static_cast<std::ptrdiff_t>(spacing.size() / 2);
    std::nth_element(spacing.begin(), mid, spacing.end());
    probe.median_spacing_us = *mid;
  }
  return probe;
}

}  // namespace vlpground::cli
