// rollwear: the one binary (service/cli.h). The only file that sees the
// version and the git commit (compile definitions from CMake), so a new
// commit recompiles nothing else.
#include "service/cli.h"

#ifndef ROLLWEAR_VERSION
#error "ROLLWEAR_VERSION must be defined (service/CMakeLists.txt)"
#endif
#ifndef ROLLWEAR_GIT_COMMIT
#error "ROLLWEAR_GIT_COMMIT must be defined (service/CMakeLists.txt)"
#endif

int main(int argc, char** argv) {
  return rollwear::cli::RunCli(argc, argv,
                               "rollwear " ROLLWEAR_VERSION
                               " (commit " ROLLWEAR_GIT_COMMIT ")");
}
