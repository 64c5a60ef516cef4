// Router's handlers of the wear profile across the barrel: POST
// /v1/profiles (a grinder profile, stored by MillStore::AddProfile) and GET
// /v1/wear/{stand}/{position}/profile (docs/api.md).
//
// Thread-safety: as Router (router.h).
#include <optional>
#include <string>
#include <utility>

#include "api/codec.h"
#include "api/router.h"
#include "api/router_internal.h"

namespace rollwear::api {

using router_internal::Answer;
using router_internal::Error;
using router_internal::FromStatus;

HttpResponse Router::PostProfile(const HttpRequest& request) {
  storage::ProfileIn in;
  ApiError error;
  if (!DecodeProfile(request.body, options_.max_json_depth, &in, &error)) {
    return Error(error);
  }
  StatusOr<storage::WriteOutcome> outcome = store_->AddProfile(in);
  if (!outcome.ok()) return FromStatus(outcome.status());
  return Answer(*outcome == storage::WriteOutcome::kCreated ? 201 : 200,
                EncodeProfileAnswer(in, *outcome));
}

HttpResponse Router::GetWearProfile(const std::string& stand_text,
                                   const std::string& position_text) {
  int stand = 0;
  Position position;
  if (std::optional<HttpResponse> unknown = router_internal::ParseRollPosition(
          stand_text, position_text, &stand, &position)) {
    return std::move(*unknown);
  }
  StatusOr<storage::ProfileWear> wear = store_->WearProfileAt(stand, position);
  if (!wear.ok()) return FromStatus(wear.status());
  return Answer(200, EncodeWearProfile(*wear));
}

}  // namespace rollwear::api
