// Diagnosis jobs as the router sees them: POST /v1/diagnoses queues one,
// GET /v1/diagnoses/{id} reads it back, the dashboard shows the latest
// finding. The jobs themselves run in the service layer
// (service/jobs/diagnosis_jobs.h, which implements DiagnosisRunner and is
// handed to the Router at start-up through ApiOptions::diagnoses), so api
// does not include service.
//
// Thread-safety: DiagnosisJob is a plain value; implementations of
// DiagnosisRunner must be thread-safe (the router calls them from any
// request thread).
#ifndef ROLLWEAR_API_DIAGNOSIS_JOB_H_
#define ROLLWEAR_API_DIAGNOSIS_JOB_H_

#include <cstdint>
#include <optional>
#include <string>

#include "storage/store_types.h"

namespace rollwear::api {

struct DiagnosisJob {
  int64_t id = 0;
  std::string status;   // "queued", "running", "done", "failed"
  std::string report;   // JSON of api/diagnosis_json.h when done
  std::string message;  // why it failed
  bool adopt = false;
  // The run that proposed the adopted model (adopt and missing physics).
  std::optional<storage::CalibrationRecord> adoption;
  // When it was queued, started and finished (0: not yet), its verdict (the
  // report's, when done) and the HTML report of `rollwear diagnose --html`
  // (when done): what is stored once it has finished
  // (MillStore::SaveDiagnosis).
  UnixSeconds queued_at = 0, started_at = 0, finished_at = 0;
  std::string verdict;
  std::string html;
};

// {"id", "status"} plus, when done, every field of the report (the JSON of
// `rollwear diagnose --json`) and, when a model was proposed, "adoption":
// {"calibration_id", "promoted", "gap_val_um", "active_gap_val_um",
// "model_version", "message"}; "message" when failed.
std::string EncodeDiagnosisJob(const DiagnosisJob& job);

// What the router needs of the daemon's diagnosis jobs.
class DiagnosisRunner {
 public:
  virtual ~DiagnosisRunner() = default;
  // Queues a diagnosis of everything the store holds (proposing its
  // adopted model when `adopt`) and returns its id (> 0).
  virtual int64_t Enqueue(bool adopt) = 0;
  // The job `id`, or nothing when unknown (never queued, or evicted).
  virtual std::optional<DiagnosisJob> Get(int64_t id) const = 0;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_DIAGNOSIS_JOB_H_
