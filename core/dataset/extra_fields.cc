#include "core/dataset/extra_fields.h"

#include <cmath>

namespace rollwear {

ExtraFields ExtraFieldsOfRow(const ExtraColumns& columns, size_t row) {
  ExtraFields f;
  for (size_t c = 0; c < columns.numeric_names.size(); ++c) {
    const double v = columns.numeric[c][row];
    if (!std::isnan(v)) f.numeric.emplace_back(columns.numeric_names[c], v);
  }
  for (size_t c = 0; c < columns.factor_names.size(); ++c) {
    f.factor.emplace_back(columns.factor_names[c],
                          columns.factor_levels[c][columns.factor[c][row]]);
  }
  f.Sort();
  return f;
}

ExtraFields MergedExtraFields(const ExtraFields& a, const ExtraFields& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  ExtraFields out = b;
  for (const auto& [name, v] : a.numeric) {
    if (b.Numeric(name) == nullptr) out.numeric.emplace_back(name, v);
  }
  for (const auto& [name, v] : a.factor) {
    if (b.Factor(name) == nullptr) out.factor.emplace_back(name, v);
  }
  out.Sort();
  return out;
}

}  // namespace rollwear
