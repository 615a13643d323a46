// Subcommands of the `vlpground` executable. Each returns the process exit code.
#pragma once

namespace vlpground::cli {

int run_replay(int argc, char** argv);
int run_live(int argc, char** argv);
int run_info(int argc, char** argv);
int run_eval(int argc, char** argv);
int run_sim(int argc, char** argv);

}  // namespace vlpground::cli
