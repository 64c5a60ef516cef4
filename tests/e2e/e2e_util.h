// Helpers of e2e_test: run the real `rollwear` binary (its path is the
// compile definition ROLLWEAR_BINARY) as subprocesses - the daemon on an
// ephemeral loopback port with a temporary SQLite file, `simulate`,
// `replay` - and read its answers: /v1/wear, /metrics counters, and the
// offline batch prediction of a dataset under a model's coefficients.
//
// Thread-safety: test helpers; a Subprocess is used from one thread.
#ifndef ROLLWEAR_TESTS_E2E_E2E_UTIL_H_
#define ROLLWEAR_TESTS_E2E_E2E_UTIL_H_

#include <sys/types.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/wear_model.h"

namespace rollwear::e2e {

using json = nlohmann::json;

// A temporary folder, removed with its content on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const {
    return path_ + "/" + name;
  }

 private:
  std::string path_;
};

// A child process with stdout and stderr appended to `log_path`.
class Subprocess {
 public:
  // `env` entries "NAME=value" are added to (or override) the environment.
  // With `stderr_path`, stderr goes there instead of to `log_path`.
  Subprocess(const std::vector<std::string>& argv, const std::string& log_path,
             const std::vector<std::string>& env = {},
             const std::string& stderr_path = "");
  ~Subprocess();  // SIGKILLs and reaps a child still running

  pid_t pid() const { return pid_; }
  bool Running();
  void Signal(int sig);
  // Waits for the exit; returns the exit code, or -signal when killed, or
  // -1000 when `timeout_s` passed (the child is then left running).
  int Wait(double timeout_s = 600);

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
};

// Runs the rollwear binary to completion; returns its exit code and puts
// its output in *output.
int RunRollwear(const std::vector<std::string>& args, std::string* output,
                double timeout_s = 600);

// The same with stdout and stderr kept apart.
int RunRollwear(const std::vector<std::string>& args, std::string* out,
                std::string* err, double timeout_s = 600);

// Reads a whole file ("" when missing).
std::string ReadFile(const std::string& path);

// `rollwear serve` on loopback with the database `db`.
class Daemon {
 public:
  // port 0: ephemeral (the bound port is read from the daemon's first line).
  Daemon(std::string db, std::string log_path, int port = 0,
         std::vector<std::string> extra_args = {},
         std::vector<std::string> env = {});
  // Starts and waits for "listening on"; false (with the log) on failure.
  bool Start(std::string* error);
  void Kill9();
  // SIGTERM and wait; returns the exit code.
  int Terminate();
  int port() const { return port_; }
  std::string url() const {
    return "http://127.0.0.1:" + std::to_string(port_);
  }
  Subprocess* process() { return process_.get(); }

 private:
  std::string db_, log_path_;
  int port_;
  std::vector<std::string> extra_args_, env_;
  std::unique_ptr<Subprocess> process_;
};

// GET `path` from `url`; status 0 when no answer.
int HttpGet(const std::string& url, const std::string& path, json* body);
int HttpPost(const std::string& url, const std::string& path,
             const std::string& body, json* answer,
             const std::string& token = "");
// GETs `path` (a job: a calibration or a diagnosis) every 100 ms until its
// "status" is "done" or "failed", an answer is not 200, or `timeout_s`
// passed; returns the last answer.
json WaitForJob(const std::string& url, const std::string& path,
                double timeout_s = 600);
// Plain-number samples of GET /metrics without labels ("rollwear_coils_stored"
// -> 1234).
std::map<std::string, double> ScrapeMetrics(const std::string& url);

// Simulates a dataset into `dir` (rollwear simulate --campaigns N).
bool Simulate(const std::string& dir, int campaigns, int seed,
              std::string* error);

// The wear model of a model answer (GET /v1/models/active): its law,
// option and coefficients (1 where one is missing) on `data`'s structure.
StatusOr<WearModel> ModelOfAnswer(const Dataset& data, const json& model);

// Predicted centre wear of each (campaign, stand, position) of `data`
// under the coefficients of a model answer (GET /v1/models/active), as a
// batch over whole campaigns (core's aggregation), keyed "C|F6/top".
std::map<std::string, double> OfflinePrediction(const Dataset& data,
                                                const json& model);

// The /v1/wear positions keyed "C|F6/top" -> predicted_wear_um.
std::map<std::string, double> WearByKey(const json& wear);

// Request bodies for campaign `c` / coil `k` of `data` (as rollwear replay
// sends them).
json RollChangeJson(const Dataset& data, int c);
json CoilJson(const Dataset& data, int k);
// Coil indices of campaign `c`, by seq.
std::vector<int> CoilsOf(const Dataset& data, int c);

}  // namespace rollwear::e2e

#endif  // ROLLWEAR_TESTS_E2E_E2E_UTIL_H_
