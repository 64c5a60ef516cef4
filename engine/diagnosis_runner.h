// A diagnosis job as the daemon keeps it, and what the router needs of
// the jobs: POST /v1/diagnoses queues one, GET /v1/diagnoses/{id} reads it
// back, the dashboard shows the latest finding. The jobs run in
// engine/diagnosis_jobs.h (which implements DiagnosisRunner and is handed
// to the Router at start-up through api::ApiOptions::diagnoses).
//
// Thread-safety: DiagnosisJob is a plain value; implementations of
// DiagnosisRunner must be thread-safe (the router calls them from any
// request thread).
#ifndef ROLLWEAR_ENGINE_DIAGNOSIS_RUNNER_H_
#define ROLLWEAR_ENGINE_DIAGNOSIS_RUNNER_H_

#include <cstdint>
#include <optional>
#include <string>

#include "storage/store_types.h"

namespace rollwear::engine {

struct DiagnosisJob {
  int64_t id = 0;
  std::string status;  // "queued", "running", "done", "failed"
  std::string
      report;  // the report's JSON text when done (api/diagnosis_json.h)
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

}  // namespace rollwear::engine

#endif  // ROLLWEAR_ENGINE_DIAGNOSIS_RUNNER_H_
