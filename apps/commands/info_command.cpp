#include <cstdio>

#include "commands/commands.hpp"

namespace vlpground::cli {

int run_info(int /*argc*/, char** /*argv*/) {
  std::fprintf(stderr, "vlpground info: not implemented yet\n");
  return 2;
}

}  // namespace vlpground::cli
