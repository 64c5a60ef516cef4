// DiagnosisJobs: runs diagnoses (core/diagnosis/diagnosis.h) of everything
// the store holds, one at a time on a background worker, for POST
// /v1/diagnoses and GET /v1/diagnoses/{id} (it is the router's
// api::DiagnosisRunner). Each finished diagnosis (done or failed, with its
// JSON and HTML reports) is stored (MillStore::SaveDiagnosis) before it is
// shown finished, so it outlives a restart; ids go on after the stored
// ones. Jobs are also kept in memory (the last 50) for queued and running
// ones. A diagnosis queued with `adopt` that finds
// missing physics proposes its adopted model (option 1 plus the fitted
// terms) to the store, which promotes it when its validation gap is no
// worse than the active model's (engine::CalibrationRuns::Propose); the job
// then carries that run's record. Every job logs its start and end
// (service/jobs/job_log.h); the adoption's run is handed to
// `on_calibration` like every other calibration run (metrics, log).
//
// Thread-safety: all methods are thread-safe. Stop() (and the destructor)
// waits for a running diagnosis to finish; queued ones are dropped.
#ifndef ROLLWEAR_SERVICE_JOBS_DIAGNOSIS_JOBS_H_
#define ROLLWEAR_SERVICE_JOBS_DIAGNOSIS_JOBS_H_

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "api/diagnosis_job.h"
#include "engine/calibration_runs.h"
#include "storage/mill_store.h"

namespace rollwear::service {

class DiagnosisJobs final : public api::DiagnosisRunner {
 public:
  // The calibration run of an adoption and its wall time, seconds.
  using CalibrationDone =
      std::function<void(const storage::CalibrationRecord&, double)>;
  // `store` and `runs` (the engine's, on that store) must outlive the
  // worker (this object, or until Stop()). `on_calibration` (may be empty)
  // runs on the worker thread.
  DiagnosisJobs(storage::MillStore* store, engine::CalibrationRuns* runs,
                CalibrationDone on_calibration = nullptr);
  ~DiagnosisJobs() override;  // Stop()s
  DiagnosisJobs(const DiagnosisJobs&) = delete;
  DiagnosisJobs& operator=(const DiagnosisJobs&) = delete;

  // Queues a diagnosis and returns its id.
  int64_t Enqueue(bool adopt) override;
  std::optional<api::DiagnosisJob> Get(int64_t id) const override;
  // Stops the worker; idempotent.
  void Stop();

 private:
  void Work();
  // Runs diagnosis `id` on the stored data (worker thread, no lock held).
  api::DiagnosisJob Run(int64_t id, bool adopt);

  storage::MillStore* store_;
  engine::CalibrationRuns* runs_;
  CalibrationDone on_calibration_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<int64_t> queue_;
  std::map<int64_t, api::DiagnosisJob> jobs_;
  int64_t next_id_ = 1;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace rollwear::service

#endif  // ROLLWEAR_SERVICE_JOBS_DIAGNOSIS_JOBS_H_
