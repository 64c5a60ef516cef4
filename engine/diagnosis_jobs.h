// DiagnosisJobs: runs diagnoses (core/diagnosis/diagnosis.h) of everything
// the store holds, one at a time on a background worker, for POST
// /v1/diagnoses and GET /v1/diagnoses/{id} (it is the router's
// DiagnosisRunner, engine/diagnosis_runner.h). Each finished diagnosis (done or
// failed, with its JSON and HTML reports) is stored (MillStore::SaveDiagnosis)
// before it is shown finished, so it outlives a restart; ids go on after the
// stored ones. Jobs are also kept in memory (the last 50) for queued and
// running ones. A diagnosis queued with `adopt` that finds missing physics
// proposes its adopted model (option 1 plus the fitted terms) to the store,
// which promotes it when its validation gap is no worse than the active model's
// (engine::CalibrationRuns::Propose); the job then carries that run's record.
// The daemon hands in what the engine may not include (DiagnosisJobHooks): the
// report's JSON text (api/diagnosis_json.h), the log lines of a job's start and
// end (service/jobs/job_log.h), and what it does with every calibration run
// (metrics, log), which the adoption's run is handed to.
//
// Thread-safety: all methods are thread-safe. Stop() (and the destructor)
// waits for a running diagnosis to finish; queued ones are dropped.
#ifndef ROLLWEAR_ENGINE_DIAGNOSIS_JOBS_H_
#define ROLLWEAR_ENGINE_DIAGNOSIS_JOBS_H_

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/dataset/data_quality.h"
#include "core/diagnosis/diagnosis.h"
#include "engine/calibration_runs.h"
#include "engine/diagnosis_runner.h"
#include "storage/mill_store.h"

namespace rollwear::engine {

// What the daemon hands its diagnosis jobs (each runs on the worker
// thread; all but report_json may be empty).
struct DiagnosisJobHooks {
  // The JSON text of a finished report and the stored data's quality (the
  // body of `rollwear diagnose --json`).
  std::function<std::string(const DiagnosisReport&, const DataQuality&)>
      report_json;
  // A job's start, and its end with its wall time in seconds.
  std::function<void(int64_t id, bool adopt)> on_started;
  std::function<void(const DiagnosisJob&, double)> on_finished;
  // The calibration run of an adoption and its wall time, seconds.
  std::function<void(const storage::CalibrationRecord&, double)> on_calibration;
};

class DiagnosisJobs final : public DiagnosisRunner {
 public:
  // `store` and `runs` (the engine's, on that store) must outlive the
  // worker (this object, or until Stop()). Without `hooks.report_json`
  // every job fails with a message saying so (a wiring fault the first
  // diagnosis shows, rather than an exception).
  DiagnosisJobs(storage::MillStore* store, CalibrationRuns* runs,
                DiagnosisJobHooks hooks);
  ~DiagnosisJobs() override;  // Stop()s
  DiagnosisJobs(const DiagnosisJobs&) = delete;
  DiagnosisJobs& operator=(const DiagnosisJobs&) = delete;

  // Queues a diagnosis and returns its id.
  int64_t Enqueue(bool adopt) override;
  std::optional<DiagnosisJob> Get(int64_t id) const override;
  // Stops the worker; idempotent.
  void Stop();

 private:
  void Work();
  // Runs diagnosis `id` on the stored data (worker thread, no lock held).
  DiagnosisJob Run(int64_t id, bool adopt);

  storage::MillStore* store_;
  CalibrationRuns* runs_;
  const DiagnosisJobHooks hooks_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<int64_t> queue_;
  std::map<int64_t, DiagnosisJob> jobs_;
  int64_t next_id_ = 1;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace rollwear::engine

#endif  // ROLLWEAR_ENGINE_DIAGNOSIS_JOBS_H_
