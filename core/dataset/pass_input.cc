#include "core/dataset/pass_input.h"

namespace rollwear {

PassInput PassInputOf(const Dataset& data, const Pass& p) {
  return PassInputFromRow(p.grade >= 0 ? data.grades[p.grade] : std::string(), p);
}

}  // namespace rollwear
