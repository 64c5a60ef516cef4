#include "service/jobs/diagnosis_hooks.h"

#include <utility>

#include "api/diagnosis_json.h"
#include "service/jobs/job_log.h"

namespace rollwear::service {

engine::DiagnosisJobHooks DaemonDiagnosisHooks(
    std::function<void(const storage::CalibrationRecord&, double)>
        on_calibration) {
  engine::DiagnosisJobHooks hooks;
  hooks.report_json = [](const DiagnosisReport& report,
                         const DataQuality& quality) {
    return api::DiagnosisJsonText(report, -1, &quality);
  };
  hooks.on_started = LogDiagnosisStarted;
  hooks.on_finished = LogDiagnosisFinished;
  hooks.on_calibration = std::move(on_calibration);
  return hooks;
}

}  // namespace rollwear::service
