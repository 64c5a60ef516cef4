// Wear models over given level lists: the prior model the daemon predicts
// with before any calibration, and an existing model re-expressed over the
// levels of another data set (so it can be evaluated with
// PredictObservation on statistics whose level indices differ).
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_STORAGE_MODEL_LEVELS_H_
#define ROLLWEAR_STORAGE_MODEL_LEVELS_H_

#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/model/wear_model.h"

namespace rollwear::storage {

// `law`, K structure `option` over `positions` (no roll types, no grades),
// every kF = initial_k and every other factor 1; no covariance, and a noise
// model of 50 % of the predicted wear (an uncalibrated K is a guess, and the
// prediction interval says so).
StatusOr<WearModel> PriorModel(WearLaw law, int option,
                               std::vector<std::string> positions,
                               double initial_k);

// `model` over the given levels: each coefficient is taken from `model` by
// name, a level the model has never seen gets its gauge value 1 (what
// core/model/predictor.h does for unknown labels). The Cao exponent, the noise
// model and the adopted terms are kept; the covariance is kept only when the
// coefficient list is unchanged (otherwise dropped: it is not needed to
// evaluate the model). InvalidArgument for the recurrent network.
StatusOr<WearModel> ModelOverLevels(const WearModel& model,
                                    std::vector<std::string> positions,
                                    std::vector<std::string> roll_types,
                                    std::vector<std::string> grades);

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_MODEL_LEVELS_H_
