#include <cstdio>

#include "commands/commands.hpp"

namespace vlpground::cli {

int run_live(int /*argc*/, char** /*argv*/) {
  std::fprintf(stderr, "vlpground live: not implemented yet\n");
  return 2;
}

}  // namespace vlpground::cli
