#include "core/dataset/pass_input.h"

namespace rollwear {

PassInput PassInputOf(const Dataset& data, const Pass& p) {
  PassInput in =
      PassInputFromRow(p.grade >= 0 ? data.grades[p.grade] : std::string(), p);
  const size_t row = static_cast<size_t>(&p - data.passes.data());
  if (row < data.passes.size()) in.extra = ExtraFieldsOfRow(data.pass_extra, row);
  return in;
}

}  // namespace rollwear
