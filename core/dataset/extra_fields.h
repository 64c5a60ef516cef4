// ExtraFields: the extra fields of one record that arrives over the API (a
// roll change's campaign, one of its rolls, a coil, one of its passes, a
// measurement). They are the data format's extra columns
// (docs/data-format.md) in JSON form: a JSON number is a value of a numeric
// column, a JSON string (or true/false, as "true"/"false") a level of a
// factor column; null is an empty cell and is not kept. The decoders
// (api/codec.h) keep each list sorted by name, so two bodies that differ only
// in member order give equal ExtraFields (idempotent repeats compare equal).
//
// Thread-safety: plain value.
#ifndef ROLLWEAR_CORE_DATASET_EXTRA_FIELDS_H_
#define ROLLWEAR_CORE_DATASET_EXTRA_FIELDS_H_

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/dataset/dataset.h"

namespace rollwear {

struct ExtraFields {
  std::vector<std::pair<std::string, double>> numeric;       // sorted by name
  std::vector<std::pair<std::string, std::string>> factor;   // sorted by name

  bool empty() const { return numeric.empty() && factor.empty(); }
  bool operator==(const ExtraFields&) const = default;

  // The value of a numeric field, or nullptr when the record has none.
  const double* Numeric(std::string_view name) const {
    for (const auto& [n, v] : numeric) {
      if (n == name) return &v;
    }
    return nullptr;
  }
  // The level of a factor field, or nullptr when the record has none.
  const std::string* Factor(std::string_view name) const {
    for (const auto& [n, v] : factor) {
      if (n == name) return &v;
    }
    return nullptr;
  }
  // Restores the sorted order after fields were appended.
  void Sort() {
    std::sort(numeric.begin(), numeric.end());
    std::sort(factor.begin(), factor.end());
  }
};

// Row `row` of a dataset's extra columns as fields: every numeric column
// with a value (an empty cell, NaN, is left out, as a JSON null is) and every
// factor column with its level's text (the empty text included: it is a
// level of the column, data-format.md).
ExtraFields ExtraFieldsOfRow(const ExtraColumns& columns, size_t row);

// The fields of `a` and of `b` together (a coil's fields and one of its
// passes'), sorted; a name in both keeps `b`'s value.
ExtraFields MergedExtraFields(const ExtraFields& a, const ExtraFields& b);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_EXTRA_FIELDS_H_
