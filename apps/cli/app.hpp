// The whole `vlpground` command line: the CLI11 app with its subcommands, `help`, `--version`,
// and the Markdown reference of every option (docs/cli.md is generated from it).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "commands/commands.hpp"

namespace vlpground::cli {

struct CliApp {
  CLI::App app{"vlpground: VLP-16 driver with ground detection", "vlpground"};
  std::vector<std::pair<CLI::App*, std::unique_ptr<Command>>> commands;
};

/// Builds the parser (options bound to the commands' own state).
std::unique_ptr<CliApp> build_cli();

/// Parses and runs; returns the exit code (0 ok, 1 runtime failure, 2 usage error).
int run_cli(int argc, char** argv);

/// Every option of every subcommand as Markdown (`vlpground help --all-markdown`).
std::string markdown_reference(const CLI::App& app);

}  // namespace vlpground::cli
