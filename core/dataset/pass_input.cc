#include "core/dataset/pass_input.h"

#include <functional>

namespace rollwear {

PassInput PassInputOf(const Dataset& data, const Pass& p) {
  PassInput in =
      PassInputFromRow(p.grade >= 0 ? data.grades[p.grade] : std::string(), p);
  // The row's extra columns when `p` is an element of data.passes (std::less
  // orders any two pointers; a copy of a pass has no row).
  const Pass* begin = data.passes.data();
  const Pass* end = begin + data.passes.size();
  if (!std::less<const Pass*>()(&p, begin) && std::less<const Pass*>()(&p, end)) {
    in.extra = ExtraFieldsOfRow(data.pass_extra, static_cast<size_t>(&p - begin));
  }
  return in;
}

}  // namespace rollwear
