// Minimal command-line parsing for the subcommands: `--name value` / `--name=value` options
// declared up front, positionals, and typed getters that throw UsageError (one line) on bad
// input. No third-party dependency.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "vlpground/pipeline.hpp"

namespace vlpground::cli {

/// A malformed command line: printed as one line, exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct OptionSpec {
  const char* name;  // "--port"
  bool takes_value;
  const char* help;  // "N  UDP data port (default 2368)"
};

class Args {
 public:
  /// Parses argv[1..]; argv[0] is the subcommand name. Throws UsageError.
  Args(int argc, char** argv, const std::vector<OptionSpec>& specs);

  [[nodiscard]] bool has(const std::string& name) const { return values_.count(name) != 0; }
  [[nodiscard]] const std::vector<std::string>& positionals() const { return positionals_; }
  [[nodiscard]] std::string text(const std::string& name, const std::string& fallback) const;
  [[nodiscard]] double number(const std::string& name, double fallback, double lo, double hi) const;
  [[nodiscard]] std::int64_t integer(const std::string& name, std::int64_t fallback,
                                     std::int64_t lo, std::int64_t hi) const;

 private:
  std::map<std::string, std::string> values_;
  std::vector<std::string> positionals_;
};

/// "  --name VALUE  help" lines for `--help`.
std::string describe_options(const std::vector<OptionSpec>& specs);

/// Options shared by replay, live and eval: detector, decoder, assembler settings.
const std::vector<OptionSpec>& detector_option_specs();
/// Options of the outputs (replay and live).
const std::vector<OptionSpec>& output_option_specs();

/// Fills decoder / assembler / detector / pipeline settings from the common options.
void apply_common_options(const Args& args, PipelineConfig& config);

/// Where the results go.
struct OutputOptions {
  std::string csv_path;
  std::string pcd_dir;
  std::string png_dir;
  bool json = false;
  std::string log_level = "warn";
};
OutputOptions output_options(const Args& args);

/// Applies --log-level to spdlog (throws UsageError for an unknown level).
void apply_log_level(const std::string& level);

}  // namespace vlpground::cli
