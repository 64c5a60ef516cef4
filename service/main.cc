// rollwear: the one binary (service/cli.h). The only file that sees the
// version (a compile definition) and the git commit (a header generated at
// every build, service/write_build_commit.cmake), so a new commit recompiles
// nothing else.
#include "rollwear_build_commit.h"
#include "service/cli.h"

#ifndef ROLLWEAR_VERSION
#error "ROLLWEAR_VERSION must be defined (service/CMakeLists.txt)"
#endif
#ifndef ROLLWEAR_GIT_COMMIT
#error "ROLLWEAR_GIT_COMMIT must be defined (rollwear_build_commit.h)"
#endif

int main(int argc, char** argv) {
  return rollwear::cli::RunCli(argc, argv,
                               {ROLLWEAR_VERSION, ROLLWEAR_GIT_COMMIT});
}
