#include "core/model/model_family.h"

#include "core/model/ann_model.h"

namespace rollwear {

std::string ModelChoice::Name() const {
  return is_network() ? std::string(kAnnModelName) : WearLawName(law);
}

StatusOr<ModelChoice> ParseModelChoice(const std::string& name, int option) {
  if (name == kAnnModelName) return ModelChoice::Network();
  WearLaw law = WearLaw::kWang;
  if (!ParseWearLaw(name, &law)) {
    return Status::InvalidArgument("model: must be wang, nikitenko, cao or " +
                                   std::string(kAnnModelName) + ", got '" +
                                   name + "'");
  }
  if (option < 1 || option > 3) {
    return Status::InvalidArgument("option: must be 1, 2 or 3, got " +
                                   std::to_string(option));
  }
  return ModelChoice::Law(law, option);
}

}  // namespace rollwear
