#include <cstdio>

#include "commands/commands.hpp"

namespace vlpground::cli {

int run_sim(int /*argc*/, char** /*argv*/) {
  std::fprintf(stderr, "vlpground sim: not implemented yet\n");
  return 2;
}

}  // namespace vlpground::cli
