// Router's handlers of the plain read and write endpoints (roll changes,
// campaign ends, wear, calibrations, diagnoses, models, health): each
// decodes its request (api/codec.h), calls the store and answers. The
// dispatch, the token check, the asynchronous coil path, measurements and
// metrics are in router.cc.
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

HttpResponse Router::PostRollChange(const HttpRequest& request) {
  return router_internal::PostRecord(
      request, options_.max_json_depth, &DecodeRollChange,
      [this](storage::RollChangeIn* in) {
        return store_->ApplyRollChange(*in);
      },
      &EncodeRollChangeAnswer);
}

HttpResponse Router::PostCampaignEnd(const HttpRequest& request,
                                     const std::string& campaign_id) {
  UnixSeconds ended_at = 0;
  ApiError error;
  if (!DecodeCampaignEnd(request.body, options_.max_json_depth, &ended_at,
                         &error)) {
    return Error(error);
  }
  StatusOr<storage::WriteOutcome> outcome =
      store_->EndCampaign(campaign_id, ended_at);
  if (!outcome.ok()) return FromStatus(outcome.status());
  return Answer(200, EncodeCampaignEndAnswer(campaign_id, ended_at, *outcome));
}

HttpResponse Router::GetWear() {
  return Answer(200, EncodeWear(mounted_.Wear()));
}

HttpResponse Router::GetWearAt(const std::string& stand_text,
                               const std::string& position_text) {
  int stand = 0;
  Position position;
  if (std::optional<HttpResponse> unknown = router_internal::ParseRollPosition(
          stand_text, position_text, &stand, &position)) {
    return std::move(*unknown);
  }
  // The answer names the model version so that clients can tell which model
  // predicted: the one the position was read with (one moment).
  int64_t model_version = 0;
  StatusOr<engine::PositionWear> wear =
      mounted_.WearAt(stand, position, &model_version);
  if (!wear.ok()) return FromStatus(wear.status());
  return Answer(200, EncodePositionWear(*wear, model_version));
}

HttpResponse Router::PostCalibration(const HttpRequest& request) {
  CalibrationRequest in;
  in.law = options_.default_law;
  in.option = options_.default_option;
  ApiError error;
  if (!DecodeCalibrationRequest(request.body, options_.max_json_depth, &in,
                                &error)) {
    return Error(error);
  }
  StatusOr<int64_t> id = store_->EnqueueCalibration(
      "api",
      in.ann ? ModelChoice::Network() : ModelChoice::Law(in.law, in.option));
  if (!id.ok()) return FromStatus(id.status());
  if (options_.on_calibration_queued) options_.on_calibration_queued(*id);
  HttpResponse r = Answer(202, EncodeCalibrationId(*id));
  r.headers.emplace_back("Location", "/v1/calibrations/" + std::to_string(*id));
  return r;
}

HttpResponse Router::GetCalibration(const std::string& id_text) {
  int64_t id = 0;
  if (!ParseInt64(id_text, &id) || id <= 0) {
    return Error(404, "not_found",
                 "unknown calibration '" + id_text.substr(0, 40) + "'");
  }
  StatusOr<storage::CalibrationRecord> record = store_->GetCalibration(id);
  if (!record.ok()) return FromStatus(record.status());
  return Answer(200, EncodeCalibration(*record));
}

HttpResponse Router::PostDiagnosis(const HttpRequest& request) {
  DiagnosisRequest in;
  ApiError error;
  if (!DecodeDiagnosisRequest(request.body, options_.max_json_depth, &in,
                              &error)) {
    return Error(error);
  }
  if (options_.diagnoses == nullptr) {
    return Error(503, "unavailable", "diagnoses are not run by this server");
  }
  const int64_t id = options_.diagnoses->Enqueue(in.adopt);
  last_diagnosis_id_.store(id, std::memory_order_relaxed);
  return Answer(202,
                "{\"id\":" + std::to_string(id) + ",\"status\":\"queued\"}");
}

HttpResponse Router::GetDiagnosis(const std::string& id_text) {
  int64_t id = 0;
  std::optional<engine::DiagnosisJob> job;
  if (ParseInt64(id_text, &id) && id > 0) {
    if (options_.diagnoses != nullptr) job = options_.diagnoses->Get(id);
    // Finished ones outlive a restart in the store (router_shop.cc).
    if (!job) job = StoredDiagnosisJob(id);
  }
  if (!job) {
    return Error(404, "not_found",
                 "unknown diagnosis '" + id_text.substr(0, 40) + "'");
  }
  return Answer(200, EncodeDiagnosisJob(*job));
}

HttpResponse Router::ListCalibrations(const HttpRequest& request) {
  int64_t limit = 0;
  if (std::optional<HttpResponse> bad =
          router_internal::ReadLimit(request, &limit)) {
    return std::move(*bad);
  }
  return Answer(200, EncodeCalibrationList(
                         store_->ListCalibrations(static_cast<int>(limit))));
}

HttpResponse Router::GetActiveModel() {
  StatusOr<storage::ModelVersion> model = store_->ActiveModel();
  if (!model.ok()) return FromStatus(model.status());
  return Answer(200, EncodeModel(*model));
}

HttpResponse Router::ListModels(const HttpRequest& request) {
  return Answer(200, EncodeModelList(store_->ListModels()));
}

HttpResponse Router::GetHealth() {
  const bool healthy = store_->Healthy();
  return Answer(healthy ? 200 : 503, EncodeHealth(healthy));
}

}  // namespace rollwear::api
