// DiagnosisJobs: runs diagnoses (core/diagnosis/diagnosis.h) of everything the store
// holds, one at a time on a background worker, for POST /v1/diagnoses and
// GET /v1/diagnoses/{id}. Reports are kept in memory (the last 50); a
// diagnosis can always be run again from the stored data, so they are not
// persisted across restarts. A diagnosis queued with `adopt` that finds
// missing physics proposes its adopted model (option 1 plus the fitted
// terms) to the store, which promotes it when its validation gap is no worse
// than the active model's (MillStore::ProposeModel); the job then carries
// that run's record.
//
// Thread-safety: all methods are thread-safe. The destructor waits for a
// running diagnosis to finish.
#ifndef ROLLWEAR_API_DIAGNOSIS_JOBS_H_
#define ROLLWEAR_API_DIAGNOSIS_JOBS_H_

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "storage/mill_store.h"

namespace rollwear::api {

struct DiagnosisJob {
  int64_t id = 0;
  std::string status;   // "queued", "running", "done", "failed"
  std::string report;   // JSON of api/diagnosis_json.h when done
  std::string message;  // why it failed
  bool adopt = false;
  // The run that proposed the adopted model (adopt and missing physics).
  std::optional<storage::CalibrationRecord> adoption;
};

// {"id", "status"} plus, when done, every field of the report (the JSON of
// `rollwear diagnose --json`) and, when a model was proposed, "adoption":
// {"calibration_id", "promoted", "gap_val_um", "active_gap_val_um",
// "model_version", "message"}; "message" when failed.
std::string EncodeDiagnosisJob(const DiagnosisJob& job);

class DiagnosisJobs {
 public:
  // `store` must outlive this object.
  explicit DiagnosisJobs(storage::MillStore* store);
  ~DiagnosisJobs();
  DiagnosisJobs(const DiagnosisJobs&) = delete;
  DiagnosisJobs& operator=(const DiagnosisJobs&) = delete;

  // Queues a diagnosis and returns its id.
  int64_t Enqueue(bool adopt = false);
  std::optional<DiagnosisJob> Get(int64_t id) const;

 private:
  void Work();

  storage::MillStore* store_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<int64_t> queue_;
  std::map<int64_t, DiagnosisJob> jobs_;
  int64_t next_id_ = 1;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_DIAGNOSIS_JOBS_H_
