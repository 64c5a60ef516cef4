// Internal to the api codec (codec_encode.cc, codec_shop.cc,
// codec_profile.cc): the small
// helpers of the answers built as an nlohmann DOM.
//
// Thread-safety: stateless functions.
#ifndef ROLLWEAR_API_CODEC_JSON_UTIL_H_
#define ROLLWEAR_API_CODEC_JSON_UTIL_H_

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "core/dataset/timestamp.h"
#include "storage/store_types.h"

namespace rollwear::api::codec_internal {

// Insertion-ordered objects: answers list their fields in the documented
// order.
using Json = nlohmann::ordered_json;

inline std::string Dump(const Json& j) {
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

inline Json TimeOrNull(UnixSeconds t) {
  return t == 0 ? Json(nullptr) : Json(FormatTimestamp(t));
}

inline Json FiniteOrNull(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

// The "outcome" member of a write's answer.
inline const char* OutcomeName(storage::WriteOutcome o) {
  return o == storage::WriteOutcome::kCreated ? "created" : "unchanged";
}

}  // namespace rollwear::api::codec_internal

#endif  // ROLLWEAR_API_CODEC_JSON_UTIL_H_
