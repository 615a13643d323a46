// Looks at the raw packets of a capture (no decoding) to tell which sensor made it: product
// byte, return-mode byte and packet spacing. Used by `info`, and by `replay`/`eval` to refuse
// a file with no VLP-16 packets with a one-line reason.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "vlpground/driver/packet_source.hpp"

namespace vlpground::cli {

struct CaptureProbe {
  std::string error;               // the file could not be opened / read (one line)
  std::uint64_t data_packets = 0;  // inspected
  SourceCounters counters;
  std::map<std::uint8_t, std::uint64_t> product_bytes, mode_bytes;
  double median_spacing_us = 0;                  // between consecutive data packet stamps
  double first_stamp_s = -1, last_stamp_s = -1;  // packet stamps, seconds past the hour

  /// "VLP-16", "Puck Hi-Res", "HDL-32E", "VLP-32C" or "unknown".
  [[nodiscard]] std::string family() const;
  /// True when the packet spacing is the VLP-16 family's for the announced return mode.
  [[nodiscard]] bool timing_is_vlp16() const;
  [[nodiscard]] bool is_vlp16() const;
  [[nodiscard]] std::uint8_t main_product() const;
  [[nodiscard]] std::uint8_t main_mode() const;
  /// One line: what was found ("HDL-32E data: product byte 0x21, 553 us packet spacing").
  [[nodiscard]] std::string verdict() const;
};

/// Reads up to `max_data_packets` data packets (0 = the whole file). Never throws.
CaptureProbe probe_capture(const PcapSourceConfig& config, std::uint64_t max_data_packets);

}  // namespace vlpground::cli
