// The model a calibration run fits, as a typed choice: a wear law with its K
// structure (option 1..3), or the recurrent network that estimates K coil by
// coil (ann_model.h). Runs and model versions store its name (the API's
// `model` field: "wang", "nikitenko", "cao" or "ann"); ParseModelChoice
// reads a stored name back once, so no code below it compares strings that
// mean either a law or the network.
//
// Thread-safety: plain values and pure functions.
#ifndef ROLLWEAR_CORE_MODEL_MODEL_FAMILY_H_
#define ROLLWEAR_CORE_MODEL_MODEL_FAMILY_H_

#include <string>

#include "core/base/status.h"
#include "core/model/wear_law.h"

namespace rollwear {

enum class ModelFamily { kWearLaw, kNetwork };

struct ModelChoice {
  ModelFamily family = ModelFamily::kWearLaw;
  WearLaw law = WearLaw::kWang;  // kWearLaw only
  int option = 1;                // kWearLaw only: the K structure, 1..3

  static ModelChoice Law(WearLaw law, int option) {
    return {ModelFamily::kWearLaw, law, option};
  }
  static ModelChoice Network() { return {ModelFamily::kNetwork}; }
  bool is_network() const { return family == ModelFamily::kNetwork; }
  // The stored name: the law's (WearLawName) or "ann" (kAnnModelName).
  std::string Name() const;
};

// The choice a stored name and option stand for (the option is not read for
// "ann"). InvalidArgument "model: ..." for an unknown name, "option: ..."
// for a law's option outside 1..3.
StatusOr<ModelChoice> ParseModelChoice(const std::string& name, int option);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_MODEL_FAMILY_H_
