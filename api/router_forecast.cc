// Router's handlers of the remaining-life endpoints: GET /v1/limits, POST
// /v1/limits/{stand}/{position} (token) and POST /v1/forecast (token, as
// every POST: it writes nothing but may plan up to max_forecast_coils coils,
// so it is not open to anyone who can reach the port).
//
// Thread-safety: as Router (router.h).
#include <string>
#include <vector>

#include "api/codec.h"
#include "api/router.h"
#include "api/router_internal.h"

namespace rollwear::api {

using router_internal::Answer;
using router_internal::Error;
using router_internal::FromStatus;

HttpResponse Router::GetLimits() {
  return Answer(200, EncodeWearLimits(store_->WearLimits()));
}

HttpResponse Router::PostLimit(const HttpRequest& request,
                               const std::string& stand_text,
                               const std::string& position_text) {
  storage::WearLimitIn in;
  in.stand = ParseStand(stand_text);
  if (in.stand == 0 || !ParsePosition(position_text, &in.position)) {
    return Error(404, "not_found",
                 "unknown roll position '" + stand_text.substr(0, 40) + "/" +
                     position_text.substr(0, 40) +
                     "' (stands F1..F7, positions top or bottom)");
  }
  ApiError error;
  if (!DecodeWearLimit(request.body, options_.max_json_depth, &in, &error)) {
    return Error(error);
  }
  StatusOr<storage::WearLimit> limit = store_->SetWearLimit(in);
  if (!limit.ok()) return FromStatus(limit.status());
  return Answer(200, EncodeWearLimit(*limit));
}

HttpResponse Router::PostForecast(const HttpRequest& request) {
  std::vector<storage::CoilIn> coils;
  ApiError error;
  if (!DecodeForecast(request.body, options_.max_json_depth,
                      options_.max_forecast_coils, &coils, &error)) {
    return Error(error);
  }
  StatusOr<engine::Forecast> forecast = mounted_.ForecastCoils(coils);
  if (!forecast.ok()) return FromStatus(forecast.status());
  return Answer(200, EncodeForecast(*forecast));
}

}  // namespace rollwear::api
