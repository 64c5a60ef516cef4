// Internal to the router (router.cc, router_handlers.cc, router_profile.cc):
// building answers, one record's POST (decode, write, answer), the one
// translation of a store/core Status into an HTTP error, and the parsing of
// integer path parameters.
//
// Thread-safety: stateless functions.
#ifndef ROLLWEAR_API_ROUTER_INTERNAL_H_
#define ROLLWEAR_API_ROUTER_INTERNAL_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "api/codec.h"
#include "api/router.h"
#include "core/base/status.h"
#include "core/model/model_terms.h"

namespace rollwear::api::router_internal {

// An answer with `status` and a JSON `body`.
HttpResponse Answer(int status, std::string body);
// The error answer of `e` (503 adds Retry-After, 401 WWW-Authenticate).
HttpResponse Error(const ApiError& e);
HttpResponse Error(int status, std::string code, std::string message,
                   std::string field = "");
// The one translation of a store/core error into an HTTP error answer. A
// bad field (400) and an inconsistent one (422) name it.
HttpResponse FromStatus(const Status& status);

// A POST of one record (a roll change, a measurement, a profile): the body
// decoded by `decode` (codec.h's Decode*, the field's error answered when
// it fails), written by `write` (a store call: StatusOr<WriteOutcome>, may
// fill `in`), and answered 201 when created, 200 when it repeats a stored
// record, with `encode`'s body; a store error through FromStatus.
template <typename In, typename Write>
HttpResponse PostRecord(const HttpRequest& request, int max_json_depth,
                        bool (*decode)(std::string_view, int, In*, ApiError*),
                        Write write,
                        std::string (*encode)(const In&,
                                              storage::WriteOutcome)) {
  In in;
  ApiError error;
  if (!decode(request.body, max_json_depth, &in, &error)) return Error(error);
  StatusOr<storage::WriteOutcome> outcome = write(&in);
  if (!outcome.ok()) return FromStatus(outcome.status());
  return Answer(*outcome == storage::WriteOutcome::kCreated ? 201 : 200,
                encode(in, *outcome));
}
// The roll position of the path parameters of /v1/wear/{stand}/{position}
// (and .../profile), or the 404 answer naming them.
std::optional<HttpResponse> ParseRollPosition(const std::string& stand_text,
                                              const std::string& position_text,
                                              int* stand, Position* position);
// A whole decimal int64 (no sign other than '-', no spaces).
bool ParseInt64(std::string_view text, int64_t* out);
// The query parameter limit=N (1..1000, default 50) of a list endpoint in
// *limit, or the 400 answer naming `limit`.
std::optional<HttpResponse> ReadLimit(const HttpRequest& request,
                                      int64_t* limit);

}  // namespace rollwear::api::router_internal

#endif  // ROLLWEAR_API_ROUTER_INTERNAL_H_
