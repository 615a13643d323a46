// `--config FILE.yaml` of live and replay: a YAML mapping of long option names (without
// dashes) to values. A scalar is one value, a sequence of scalars several (`extrinsics: [0, 0,
// 1.8, 0, 0, 0]`, repeated options); `true`/`false` for flags. An option given on the command
// line wins over the file.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace vlpground::cli {

/// Adds `--config FILE.yaml` to `cmd`.
void add_config_file_option(CLI::App& cmd);

/// After parsing: when `cmd` was given --config, applies the file's options that the command
/// line did not set, with the same checks. Throws CLI::ParseError naming the file and key.
void apply_config_file(CLI::App& cmd);

}  // namespace vlpground::cli
