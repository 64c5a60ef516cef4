// rollwear: the one binary. Dispatches to the sub-commands of
// service/commands.h.
#include <cstdio>
#include <cstring>
#include <string>

#include "service/commands.h"

namespace {

void PrintUsage() {
  std::fprintf(stderr,
               "usage: rollwear <command> [options]\n"
               "commands:\n"
               "  simulate  --out DIR [--seed N] [--effect NAME]...   write a synthetic mill dataset\n"
               "  calibrate --data DIR [--model wang|nikitenko|cao] [--option 1|2|3] [--json FILE]\n"
               "  study     --data DIR [--out DIR]                     the study's Tables 1-3\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "-h") == 0) {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  rollwear::cli::Args args(argv + 2, argv + argc);
  if (command == "simulate") return rollwear::cli::RunSimulate(args);
  if (command == "calibrate") return rollwear::cli::RunCalibrate(args);
  if (command == "study") return rollwear::cli::RunStudy(args);
  std::fprintf(stderr, "rollwear: unknown command '%s'\n", command.c_str());
  PrintUsage();
  return 2;
}
