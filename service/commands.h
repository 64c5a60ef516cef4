// The `rollwear` CLI sub-commands: each one's parsed arguments and its entry
// point. service/cli.cc declares every option (CLI11) and fills these
// structs; the defaults below are the defaults `rollwear COMMAND --help`
// shows. Each Run* returns the process exit code (0 ok, 1 failure, 2 usage
// error); errors go to stderr as one clear sentence.
//
// Thread-safety: called once from main().
#ifndef ROLLWEAR_SERVICE_COMMANDS_H_
#define ROLLWEAR_SERVICE_COMMANDS_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/ann/ann_study.h"
#include "core/diagnosis/diagnosis.h"
#include "core/fit/calibration.h"
#include "core/fit/study.h"
#include "core/sim/simulator.h"

namespace rollwear::cli {

// The build's version and git commit (only main.cc sees them: a new commit
// recompiles nothing else); `rollwear --version` and rollwear_build_info.
struct BuildVersion {
  std::string version;  // "1.4.0"
  std::string commit;   // short hash, or "unknown"
};

struct SimulateArgs {
  std::string out;
  std::string truth;                 // empty: DIR.truth.json beside DIR
  std::vector<std::string> effects;  // --effect values (comma lists)
  bool list_effects = false;
  SimulatorOptions options;  // seed, campaigns, coils, missing, profiles
};
int RunSimulate(const SimulateArgs& args);

struct CalibrateArgs {
  bool strict = false;  // --strict: data-quality warnings are errors
  std::string data;
  std::string model = "wang";
  std::string start = "empirical";
  std::string protocol = "exact";
  std::string json;     // empty: no JSON file
  std::string figures;  // empty: no figures
  std::string terms;    // non-empty: service/calibrate_terms.h
  std::string split;        // --split FILE (core/model/given_split.h)
  std::string predictions;  // --predictions FILE: one row per reading
  bool per_roll = false;    // --per-roll: shrunk per-roll multipliers
  uint64_t split_seed = kDefaultSplitSeed;
  CalibrationOptions options;  // option, seed
};
int RunCalibrate(const CalibrateArgs& args);

struct StudyArgs {
  bool strict = false;  // --strict: data-quality warnings are errors
  std::string data;
  std::string out;       // empty: Markdown on stdout only
  std::string figures;   // empty: no figures
  std::string split;     // --split FILE
  StudyOptions options;  // split_seed, random_start_seed
};
int RunStudy(const StudyArgs& args);

struct AnnArgs {
  bool strict = false;  // --strict: data-quality warnings are errors
  std::string data;
  std::string json;
  std::string figures;
  std::string model_out;
  std::string split;        // --split FILE
  std::string predictions;  // --predictions FILE
  std::string select = "mean";
  bool no_early_stopping = false;
  AnnComparisonOptions options;  // split seed, training, compare_adopted
};
int RunAnn(const AnnArgs& args);

struct DiagnoseArgs {
  bool strict = false;  // --strict: data-quality warnings are errors
  std::string data;
  std::string json;
  std::string html;
  std::string split;  // --split FILE
  std::string model = "wang";
  DiagnosisOptions options;  // split_seed, num_threads
};
int RunDiagnose(const DiagnoseArgs& args);

struct ScorecardArgs {
  int seeds = 5;
  uint64_t first_seed = 101;
  std::string effects;  // empty: every case (service/cmd_scorecard.cc)
  int campaigns = 395;
  int threads = 2;
  std::string json;  // empty: no JSON file
};
int RunScorecard(const ScorecardArgs& args);

struct ServeArgs {
  std::string config;  // empty: no config file
  BuildVersion build;  // for rollwear_build_info
  // (config key, value) of each --db/--port/--bind/--log-level/--threads
  // flag given; they override the file and the environment.
  std::vector<std::pair<std::string, std::string>> settings;
};
int RunServe(const ServeArgs& args);

struct ImportArgs {
  bool strict = false;  // --strict: data-quality warnings are errors
  std::string db;
  std::string dir;
};
int RunImport(const ImportArgs& args);

struct ExportArgs {
  std::string db;
  std::string out;  // missing or empty folder
};
int RunExport(const ExportArgs& args);

struct ReplayArgs {
  std::string data;
  std::string url;
  std::string token;  // empty: $ROLLWEAR_TOKEN, if set
  std::string json;
  int clients = 8;
  double speed = 0;  // 0 = as fast as possible
  double retry_for_s = 60;
  double show_wear_s = 0;  // 0 = never
  bool leave_last_open = false;
  bool quiet = false;
};
int RunReplay(const ReplayArgs& args);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_COMMANDS_H_
