// `vlpground`: one executable, subcommands replay | live | info | eval | sim | help.
#include "cli/app.hpp"

int main(int argc, char** argv) { return vlpground::cli::run_cli(argc, argv); }
