// The log lines of the daemon's background jobs, one spdlog line per event
// in one key=value format that starts with `event=`:
//   event=calibration_queued id=12 trigger=api   (or nightly)
//   event=calibration_finished id=12 trigger=nightly model=wang option=1
//     status=done gap_train_um=44.10 gap_val_um=45.80
//     active_gap_val_um=46.20 promoted=true version=5 seconds=2.4
//   event=model_promoted version=5 source=nightly
//     trigger=nightly calibration_id=12 model=wang option=1
//     gap_val_um=45.80 active_gap_val_um=46.20
//   event=diagnosis_started id=3 adopt=true
//   event=diagnosis_finished id=3 adopt=true status=done
//     verdict=missing_physics_found seconds=41.2 adoption_calibration_id=13
//     promoted=false
// (each on one line). The version a promotion replaced, and manual
// activations (POST /v1/models/{version}/activate), are in the audit trail
// (GET /v1/models/history): versions are not consecutive once a model has
// been activated by hand. `source` of a promotion is nightly, calibration
// (POST /v1/calibrations) or diagnosis (the adoption of POST
// /v1/diagnoses with adopt). A free-text field (message)
// comes last; a value with a space, " = or \ is quoted (logfmt).
//
// Thread-safety: thread-safe (spdlog's default logger).
#ifndef ROLLWEAR_SERVICE_JOBS_JOB_LOG_H_
#define ROLLWEAR_SERVICE_JOBS_JOB_LOG_H_

#include <cstdint>
#include <string>
#include <string_view>

#include "engine/diagnosis_runner.h"
#include "storage/store_types.h"

namespace rollwear::service {

// "nightly", "diagnosis" or "calibration" for a calibration's trigger
// ("nightly", "diagnosis 3", "api", "cli").
std::string_view PromotionSource(std::string_view trigger);

void LogCalibrationQueued(int64_t id, std::string_view trigger);
// The run's line, and event=model_promoted when it promoted a model.
// Versions are created only by promotions and never re-activated, so the
// model replaced is version - 1 (0 = the prior model).
void LogCalibrationFinished(const storage::CalibrationRecord& r,
                            double seconds);
void LogDiagnosisStarted(int64_t id, bool adopt);
void LogDiagnosisFinished(const engine::DiagnosisJob& job, double seconds);

}  // namespace rollwear::service

#endif  // ROLLWEAR_SERVICE_JOBS_JOB_LOG_H_
