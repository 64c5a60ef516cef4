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
               "  study     --data DIR [--out DIR]                     the study's Tables 1-3\n"
               "  ann       --data DIR [--json FILE] [--seeds N] [--split-seed N]   recurrent ANN vs classical (Table 4)\n"
               "  serve     --db FILE [--port N] [--config FILE] [--bind ADDR]   the daemon (HTTP API)\n"
               "  import    --db FILE DIR                              load a dataset folder, all-or-nothing\n"
               "  replay    --data DIR --url URL [--clients N] [--speed X]   post a dataset through the API\n"
               "  diagnose  --data DIR [--json FILE] [--html FILE]     find, name and fit missing physics\n");
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
  if (command == "serve") return rollwear::cli::RunServe(args);
  if (command == "import") return rollwear::cli::RunImport(args);
  if (command == "replay") return rollwear::cli::RunReplay(args);
  if (command == "ann") return rollwear::cli::RunAnn(args);
  if (command == "diagnose") return rollwear::cli::RunDiagnose(args);
  std::fprintf(stderr, "rollwear: unknown command '%s'\n", command.c_str());
  PrintUsage();
  return 2;
}
