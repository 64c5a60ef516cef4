// The daemon's hooks for the engine's diagnosis jobs
// (engine/diagnosis_jobs.h): the report's JSON as `rollwear diagnose
// --json` writes it (api/diagnosis_json.h), the job log lines
// (service/jobs/job_log.h), and what the daemon does with a calibration
// run (an adoption's).
//
// Thread-safety: the hooks are thread-safe when `on_calibration` is.
#ifndef ROLLWEAR_SERVICE_JOBS_DIAGNOSIS_HOOKS_H_
#define ROLLWEAR_SERVICE_JOBS_DIAGNOSIS_HOOKS_H_

#include <functional>

#include "engine/diagnosis_jobs.h"
#include "storage/store_types.h"

namespace rollwear::service {

// `on_calibration` may be empty.
engine::DiagnosisJobHooks DaemonDiagnosisHooks(
    std::function<void(const storage::CalibrationRecord&, double)>
        on_calibration = nullptr);

}  // namespace rollwear::service

#endif  // ROLLWEAR_SERVICE_JOBS_DIAGNOSIS_HOOKS_H_
