// The `rollwear` command line (CLI11): the sub-commands of service/commands.h
// with every option, `rollwear COMMAND --help` (on stdout, exit 0) and
// `rollwear --version`; usage errors name the option and exit 2.
//
// Thread-safety: called once from main().
#ifndef ROLLWEAR_SERVICE_CLI_H_
#define ROLLWEAR_SERVICE_CLI_H_

#include <string>

#include "service/commands.h"

namespace rollwear::cli {

// Parses argv, runs the chosen sub-command and returns the process exit
// code. --version prints "rollwear VERSION (commit COMMIT)".
int RunCli(int argc, char** argv, const BuildVersion& build);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_CLI_H_
