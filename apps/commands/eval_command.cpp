#include <cstdio>

#include "commands/commands.hpp"

namespace vlpground::cli {

int run_eval(int /*argc*/, char** /*argv*/) {
  std::fprintf(stderr, "vlpground eval: not implemented yet\n");
  return 2;
}

}  // namespace vlpground::cli
