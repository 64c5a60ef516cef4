// JsonNumber: a finite double as a JSON number, anything else (NaN, ±inf)
// as null: JSON has no NaN. The one definition for every JSON writer in api
// and service.
//
// Thread-safety: a pure function.
#ifndef ROLLWEAR_API_JSON_NUMBER_H_
#define ROLLWEAR_API_JSON_NUMBER_H_

#include <cmath>

#include <nlohmann/json.hpp>

namespace rollwear {

// `v` as a JSON number when finite, else null. Works for nlohmann::json and
// nlohmann::ordered_json (Json).
template <typename Json = nlohmann::json>
Json JsonNumber(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

}  // namespace rollwear

#endif  // ROLLWEAR_API_JSON_NUMBER_H_
