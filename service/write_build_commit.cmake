# Run at every build (target rollwear_build_commit, service/CMakeLists.txt):
# writes OUT, a header defining ROLLWEAR_GIT_COMMIT as the short hash of the
# source tree's HEAD ("unknown" outside a git checkout), for
# `rollwear --version`. The file is rewritten only when the commit changed,
# so a build on the same commit recompiles nothing.
#   cmake -DSOURCE_DIR=<repo> -DOUT=<header> -P write_build_commit.cmake
execute_process(
  COMMAND git rev-parse --short HEAD
  WORKING_DIRECTORY ${SOURCE_DIR}
  OUTPUT_VARIABLE commit
  OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_QUIET
  RESULT_VARIABLE result)
if(NOT result EQUAL 0 OR commit STREQUAL "")
  set(commit "unknown")
endif()
set(content "// Generated at build time by service/write_build_commit.cmake: the git\n// commit this build was made from. Do not edit.\n#define ROLLWEAR_GIT_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL content)
  file(WRITE ${OUT} "${content}")
endif()
