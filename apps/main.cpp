// `vlpground`: one executable, subcommands replay | live | info | eval | sim.
#include <cstdio>
#include <cstring>
#include <string_view>

#include "commands/commands.hpp"

namespace {

void print_usage(std::FILE* to) {
  std::fputs(
      "usage: vlpground <command> [options]\n"
      "commands:\n"
      "  replay FILE.pcap   decode a capture and detect ground\n"
      "  live               run on a sensor on the network\n"
      "  info FILE.pcap     describe a capture\n"
      "  eval FILE.pcap --labels FILE.labels   score ground labels\n"
      "  sim SCENE          write a synthetic capture with ground truth\n"
      "run 'vlpground <command> --help' for its options\n",
      to);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    print_usage(stderr);
    return 2;
  }
  const std::string_view cmd = argv[1];
  if (cmd == "-h" || cmd == "--help" || cmd == "help") {
    print_usage(stdout);
    return 0;
  }
  using namespace vlpground::cli;
  if (cmd == "replay") return run_replay(argc - 1, argv + 1);
  if (cmd == "live") return run_live(argc - 1, argv + 1);
  if (cmd == "info") return run_info(argc - 1, argv + 1);
  if (cmd == "eval") return run_eval(argc - 1, argv + 1);
  if (cmd == "sim") return run_sim(argc - 1, argv + 1);
  std::fprintf(stderr, "vlpground: unknown command '%s'\n", argv[1]);
  print_usage(stderr);
  return 2;
}
