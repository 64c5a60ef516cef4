// A diagnosis job's JSON (POST /v1/diagnoses, GET /v1/diagnoses/{id}).
// The jobs run in the engine (engine/diagnosis_jobs.h, handed to the
// Router at start-up through ApiOptions::diagnoses).
//
// Thread-safety: a pure function.
#ifndef ROLLWEAR_API_DIAGNOSIS_JOB_H_
#define ROLLWEAR_API_DIAGNOSIS_JOB_H_

#include <string>

#include "engine/diagnosis_runner.h"

namespace rollwear::api {

// {"id", "status"} plus, when done, every field of the report (the JSON of
// `rollwear diagnose --json`) and, when a model was proposed, "adoption":
// {"calibration_id", "promoted", "gap_val_um", "active_gap_val_um",
// "model_version", "message"}; "message" when failed.
std::string EncodeDiagnosisJob(const engine::DiagnosisJob& job);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_DIAGNOSIS_JOB_H_
