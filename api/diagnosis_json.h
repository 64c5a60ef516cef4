// The diagnosis report as JSON: the document of `rollwear diagnose --json`
// and of GET /v1/diagnoses/{id} (docs/api.md, docs/diagnosis.md), so the CLI
// and the daemon answer with the same fields.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_API_DIAGNOSIS_JSON_H_
#define ROLLWEAR_API_DIAGNOSIS_JSON_H_

#include <string>

#include "core/dataset/data_quality.h"
#include "core/diagnosis/diagnosis.h"

namespace rollwear::api {

// JSON text of the report; `indent` < 0 gives the compact form. With
// `quality`, the data quality of the data it diagnosed as "data_quality"
// (api/data_quality_json.h).
std::string DiagnosisJsonText(const DiagnosisReport& report, int indent = -1,
                              const DataQuality* quality = nullptr);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_DIAGNOSIS_JSON_H_
