// Internal to storage: the extra fields of an API record (ExtraFields,
// core/dataset/extra_fields.h) in the `extra` TEXT column of its row, in
// the shape an imported dataset's rows use (store_dataset.cc): one JSON
// object, a numeric field as a number, a factor field as its text. Reading
// the store back as a Dataset therefore gives the API's fields as the same
// extra columns an imported folder would.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_STORAGE_EXTRA_JSON_H_
#define ROLLWEAR_STORAGE_EXTRA_JSON_H_

#include <string>
#include <string_view>

#include "core/base/status.h"
#include "core/dataset/extra_fields.h"

namespace rollwear::storage::internal {

// The JSON object of `fields`; "" (stored as NULL) when there are none.
std::string ExtraFieldsJson(const ExtraFields& fields);

// The fields of a stored `extra` (NULL/"" -> none): numbers are numeric
// fields, strings factor fields, true/false the factor texts "true"/"false";
// null (an imported empty numeric cell) is no field. IoError when the text
// is not a JSON object.
StatusOr<ExtraFields> ParseExtraFields(std::string_view text);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_EXTRA_JSON_H_
