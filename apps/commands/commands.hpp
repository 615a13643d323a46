// Subcommands of the `vlpground` executable. Each registers itself on the CLI11 app (its
// options bound to its own config) and is run after a successful parse.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>

namespace vlpground::cli {

class Command {
 public:
  virtual ~Command() = default;
  /// Returns the process exit code (cli/options.hpp: kExitOk, kExitFailure, kExitUsage).
  virtual int run() = 0;
};

std::unique_ptr<Command> add_replay_command(CLI::App& app);
std::unique_ptr<Command> add_live_command(CLI::App& app);
std::unique_ptr<Command> add_info_command(CLI::App& app);
std::unique_ptr<Command> add_eval_command(CLI::App& app);
std::unique_ptr<Command> add_sim_command(CLI::App& app);

}  // namespace vlpground::cli
