#include "api/diagnosis_job.h"

#include <nlohmann/json.hpp>

namespace rollwear::api {

std::string EncodeDiagnosisJob(const engine::DiagnosisJob& job) {
  nlohmann::json j = nlohmann::json::object();
  if (job.status == "done") {
    j = nlohmann::json::parse(job.report, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) j = nlohmann::json::object();
  }
  j["id"] = job.id;
  j["status"] = job.status;
  if (!job.message.empty()) j["message"] = job.message;
  if (job.adoption.has_value()) {
    const storage::CalibrationRecord& r = *job.adoption;
    j["adoption"] = {{"calibration_id", r.id},
                     {"promoted", r.promoted},
                     {"gap_val_um", r.gap_val_um},
                     {"active_gap_val_um", r.active_gap_val_um},
                     {"model_version", r.model_version == 0
                                           ? nlohmann::json(nullptr)
                                           : nlohmann::json(r.model_version)},
                     {"message", r.message}};
  }
  return j.dump();
}

}  // namespace rollwear::api
