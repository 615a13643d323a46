// The command line of `vlpground`, one CLI11 parser: the option groups shared by several
// subcommands, bound straight to the config structs so each default is stated once (in the
// struct) and printed by --help.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "vlpground/pipeline.hpp"

namespace vlpground::cli {

/// Exit codes (docs/cli.md): 0 success, 1 runtime failure, 2 usage error.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

/// A command line that parses but does not make sense (checked after parsing): one line,
/// exit code 2. Name the option in the message.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The sign convention, stated once for --help, README and docs.
inline constexpr const char* kFrameConvention =
    "Frames: x forward, y left, z up; roll, pitch, yaw right-handed about x, y, z "
    "(pitch > 0 = nose down, roll > 0 = right side down).";

/// An option taking one of `choices` (names -> values) into `target`; its default is the
/// name of `target`'s current value. Use it for every enum option (typed choices).
template <typename T>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& name, T& target,
                               const std::map<std::string, T>& choices,
                               const std::string& description) {
  std::vector<std::string> names;
  std::string current;
  for (const auto& [key, value] : choices) {
    names.push_back(key);
    if (value == target) current = key;
  }
  return cmd
      .add_option_function<std::string>(
          name, [&target, choices](const std::string& v) { target = choices.at(v); }, description)
      ->check(CLI::IsMember(names))
      ->default_str(current);
}

/// --method, --calibration, --extrinsics, --cut-angle, --model, --seed, --min-sensor-height.
void add_detector_options(CLI::App& cmd, PipelineConfig& config);
/// --frames N (0 = all).
void add_frames_option(CLI::App& cmd, std::uint64_t& frames);
/// --frames, --queue.
void add_run_limit_options(CLI::App& cmd, PipelineConfig& config);
/// --log-level into `level` (validated against spdlog's names).
void add_log_level_option(CLI::App& cmd, std::string& level);
/// Throws std::runtime_error "ROLE PATH: is a directory" (no such file, permission denied)
/// unless `path` is a readable file. ROLE is what the user typed: "--calibration", "capture".
void check_input_file(const std::string& role, const std::string& path);

/// Applies --log-level to spdlog.
void apply_log_level(const std::string& level);

/// "x,y,z,roll,pitch,yaw" (spaces allowed) -> Extrinsics; throws CLI::ValidationError.
Extrinsics parse_extrinsics(const std::vector<std::string>& values);

}  // namespace vlpground::cli
