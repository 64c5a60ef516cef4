// The `data_quality` object of every tool's JSON (the CLI's dataset tools,
// service/data_quality_cli.h) and of the daemon's diagnosis
// (GET /v1/diagnoses/{id}): a DataQuality (core/dataset/data_quality.h) as
// JSON, in api/ so that both the service and the api layer can write it.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_API_DATA_QUALITY_JSON_H_
#define ROLLWEAR_API_DATA_QUALITY_JSON_H_

#include <nlohmann/json.hpp>

#include <vector>

#include "core/dataset/data_quality.h"
#include "core/fit/robust.h"

namespace rollwear::api {

// {"warnings", "suspect_measurements", "counts": {kind: n},
//  "thresholds": {"noise_sd_um", "negative_limit_um", "excess_factor"},
//  "issues": [{"kind","file","line","where","value_um","reason"}...]}
// With `outliers` (a fit's suspected gross errors, core/fit/robust.h) also
// "outlier_threshold_sd" in "thresholds" and
//  "suspected_outliers": [{"campaign_id","stand","position","set",
//    "measured_um","predicted_um","standardized_residual"}...].
nlohmann::json DataQualityJson(
    const DataQuality& quality,
    const std::vector<SuspectedOutlier>* outliers = nullptr);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_DATA_QUALITY_JSON_H_
