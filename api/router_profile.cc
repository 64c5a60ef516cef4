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
using router_internal::FromStatus;

HttpResponse Router::PostProfile(const HttpRequest& request) {
  return router_internal::PostRecord(
      request, options_.max_json_depth, &DecodeProfile,
      [this](storage::ProfileIn* in) { return store_->AddProfile(*in); },
      &EncodeProfileAnswer);
}

HttpResponse Router::GetWearProfile(const std::string& stand_text,
                                   const std::string& position_text) {
  int stand = 0;
  Position position;
  if (std::optional<HttpResponse> unknown = router_internal::ParseRollPosition(
          stand_text, position_text, &stand, &position)) {
    return std::move(*unknown);
  }
  StatusOr<engine::ProfileWear> wear = mounted_.WearProfileAt(stand, position);
  if (!wear.ok()) return FromStatus(wear.status());
  return Answer(200, EncodeWearProfile(*wear));
}

}  // namespace rollwear::api
