// Router's handlers of the roll shop's endpoints: models under control
// (GET /v1/models/{version}, POST /v1/models/{version}/activate, GET
// /v1/models/history), rolls (GET /v1/rolls, GET /v1/rolls/{roll_id}) and
// stored diagnoses (GET /v1/diagnoses, GET /v1/diagnoses/{id}/report).
// Each calls the store and answers (docs/api.md).
//
// Thread-safety: as Router (router.h).
#include <string>

#include "api/codec.h"
#include "api/router.h"
#include "api/router_internal.h"

namespace rollwear::api {

using router_internal::Answer;
using router_internal::Error;
using router_internal::FromStatus;
using router_internal::ParseInt64;
using router_internal::ReadLimit;

namespace {

HttpResponse UnknownModel(const std::string& text) {
  return Error(404, "not_found",
               "unknown model version '" + text.substr(0, 40) + "'");
}

HttpResponse UnknownDiagnosis(const std::string& text) {
  return Error(404, "not_found",
               "unknown diagnosis '" + text.substr(0, 40) + "'");
}

}  // namespace

HttpResponse Router::GetModel(const std::string& text) {
  int64_t version = 0;
  if (!ParseInt64(text, &version) || version < 0) return UnknownModel(text);
  StatusOr<storage::ModelVersion> model = store_->GetModel(version);
  if (!model.ok()) return FromStatus(model.status());
  return Answer(200, EncodeModel(*model));
}

HttpResponse Router::PostActivate(const HttpRequest& request,
                                  const std::string& text) {
  int64_t version = 0;
  if (!ParseInt64(text, &version) || version <= 0) return UnknownModel(text);
  ActivateRequest in;
  ApiError error;
  if (!DecodeActivateRequest(request.body, options_.max_json_depth, &in,
                             &error)) {
    return Error(error);
  }
  StatusOr<storage::ModelVersion> model =
      store_->ActivateModel(version, in.reason, in.pin);
  if (!model.ok()) return FromStatus(model.status());
  return Answer(200, EncodeModel(*model));
}

HttpResponse Router::GetModelHistory(const HttpRequest& request) {
  int64_t limit = 0;
  if (std::optional<HttpResponse> bad = ReadLimit(request, &limit)) {
    return std::move(*bad);
  }
  auto history = store_->ModelHistory(static_cast<int>(limit));
  if (!history.ok()) return FromStatus(history.status());
  return Answer(200, EncodeModelHistory(*history));
}

HttpResponse Router::GetRoll(const std::string& roll_id) {
  StatusOr<storage::RollLife> life = store_->GetRollLife(roll_id);
  if (!life.ok()) return FromStatus(life.status());
  return Answer(200, EncodeRollLife(*life, life->wear_factor));
}

HttpResponse Router::GetRolls() {
  auto rolls = store_->RollInventory();
  if (!rolls.ok()) return FromStatus(rolls.status());
  return Answer(200, EncodeRollInventory(*rolls));
}

HttpResponse Router::ListDiagnoses(const HttpRequest& request) {
  int64_t limit = 0;
  if (std::optional<HttpResponse> bad = ReadLimit(request, &limit)) {
    return std::move(*bad);
  }
  auto list = store_->ListDiagnoses(static_cast<int>(limit));
  if (!list.ok()) return FromStatus(list.status());
  return Answer(200, EncodeDiagnosisList(*list));
}

HttpResponse Router::GetDiagnosisReport(const std::string& text) {
  int64_t id = 0;
  if (!ParseInt64(text, &id) || id <= 0) return UnknownDiagnosis(text);
  auto stored = store_->GetDiagnosis(id);
  if (!stored.ok()) return FromStatus(stored.status());
  if (!stored->has_value()) {
    // Queued or running: known, but it has no report yet.
    std::optional<engine::DiagnosisJob> job;
    if (options_.diagnoses != nullptr) job = options_.diagnoses->Get(id);
    if (!job) return UnknownDiagnosis(text);
    return Error(422, "not_ready",
                 "diagnosis " + std::to_string(id) + " is " + job->status +
                     "; its report is served once it is done");
  }
  if ((*stored)->report_html.empty()) {
    return Error(422, "not_ready",
                 "diagnosis " + std::to_string(id) +
                     " failed and has no report: " + (*stored)->message);
  }
  HttpResponse r = Answer(200, std::move((*stored)->report_html));
  r.content_type = "text/html; charset=utf-8";
  return r;
}

std::optional<engine::DiagnosisJob> Router::StoredDiagnosisJob(
    int64_t id) const {
  auto stored = store_->GetDiagnosis(id);
  if (!stored.ok() || !stored->has_value()) return std::nullopt;
  const storage::StoredDiagnosis& d = **stored;
  engine::DiagnosisJob job;
  job.id = d.id;
  job.status = d.status;
  job.report = d.report_json;
  job.message = d.message;
  job.adopt = d.adopt;
  if (d.calibration_id > 0) {
    auto run = store_->GetCalibration(d.calibration_id);
    if (run.ok()) job.adoption = std::move(run).value();
  }
  return job;
}

}  // namespace rollwear::api
