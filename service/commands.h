// Entry points of the `rollwear` CLI sub-commands. Each takes the arguments
// after the sub-command name and returns the process exit code (0 ok,
// 1 failure, 2 usage error). Errors go to stderr as one clear sentence.
//
// Thread-safety: called once from main().
#ifndef ROLLWEAR_SERVICE_COMMANDS_H_
#define ROLLWEAR_SERVICE_COMMANDS_H_

#include <string>
#include <vector>

namespace rollwear::cli {

using Args = std::vector<std::string>;

int RunSimulate(const Args& args);
int RunCalibrate(const Args& args);
int RunStudy(const Args& args);
int RunServe(const Args& args);
int RunImport(const Args& args);
int RunReplay(const Args& args);
int RunAnn(const Args& args);
int RunDiagnose(const Args& args);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_COMMANDS_H_
