// --foxglove [ADDR:]PORT: serves the Foxglove channels of every frame (points, ground, range
// image, status) live over the Foxglove WebSocket protocol, and a web page with the
// bird's-eye view on the same port (docs/foxglove.md). Several sensors share one server.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <string>

#include "frontends/frame_sink.hpp"

namespace vlpground::cli {

inline constexpr std::uint16_t kDefaultFoxglovePort = 8765;  // Foxglove's own default
inline constexpr const char* kDefaultFoxgloveAddress = "127.0.0.1";

struct FoxgloveOptions {
  std::string listen;  // "[ADDR:]PORT" as given; empty: not requested
  // With several sensors: this sensor's name. All sensors share one server; each one's
  // channels are /vlpground/NAME/points, ... (set by outputs_for_sensor).
  std::string sensor;
};

void add_foxglove_options(CLI::App& cmd, FoxgloveOptions& o);
std::unique_ptr<FrameSink> make_foxglove_sink(const FoxgloveOptions& o,
                                              const PipelineConfig& config);

/// Splits "[ADDR:]PORT" ("8765", "0.0.0.0:8765", "[::1]:8765"); throws std::invalid_argument.
std::pair<std::string, std::uint16_t> parse_listen_address(const std::string& text);

}  // namespace vlpground::cli
