#include "api/data_quality_json.h"

namespace rollwear::api {

nlohmann::json DataQualityJson(const DataQuality& q,
                               const std::vector<SuspectedOutlier>* outliers) {
  nlohmann::json counts = nlohmann::json::object();
  for (int k = 0; k < kNumDataQualityKinds; ++k) {
    const auto kind = static_cast<DataQualityKind>(k);
    counts[DataQualityKindName(kind)] = q.Count(kind);
  }
  nlohmann::json issues = nlohmann::json::array();
  for (const DataQualityIssue& i : q.issues) {
    nlohmann::json j = {
        {"kind", DataQualityKindName(i.kind)},
        {"file", i.file},
        {"line", i.line > 0 ? nlohmann::json(i.line) : nlohmann::json(nullptr)},
        {"where", i.where},
        {"reason", i.reason}};
    j["value_um"] = i.measurement >= 0 ? nlohmann::json(i.value_um)
                                       : nlohmann::json(nullptr);
    issues.push_back(std::move(j));
  }
  nlohmann::json out = {{"warnings", q.issues.size()},
          {"suspect_measurements", q.NumSuspect()},
          {"counts", counts},
          {"thresholds",
           {{"noise_sd_um", q.noise_sd_um},
            {"negative_limit_um", -kSuspectNoiseSigmas * q.noise_sd_um},
            {"excess_factor", q.excess_factor}}},
          {"issues", issues}};
  if (outliers == nullptr) return out;
  nlohmann::json list = nlohmann::json::array();
  for (const SuspectedOutlier& o : *outliers) {
    list.push_back({{"campaign_id", o.campaign_id},
                    {"stand", "F" + std::to_string(o.stand)},
                    {"position", PositionName(o.position)},
                    {"set", o.training ? "training" : "validation"},
                    {"measured_um", o.measured_um},
                    {"predicted_um", o.predicted_um},
                    {"standardized_residual", o.standardized_residual}});
  }
  out["thresholds"]["outlier_threshold_sd"] = kOutlierSigmas;
  out["suspected_outliers"] = std::move(list);
  return out;
}

}  // namespace rollwear::api
