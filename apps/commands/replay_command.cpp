#include <cstdio>

#include "commands/commands.hpp"

namespace vlpground::cli {

int run_replay(int /*argc*/, char** /*argv*/) {
  std::fprintf(stderr, "vlpground replay: not implemented yet\n");
  return 2;
}

}  // namespace vlpground::cli
