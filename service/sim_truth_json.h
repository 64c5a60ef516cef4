// The simulator's ground truth (core/sim/simulator.h) as a JSON document,
// written beside a simulated dataset as DIR.truth.json by `rollwear
// simulate`. JSON lives here, in the service layer: core has no JSON.
//
// Thread-safety: reentrant (no shared state).
#ifndef ROLLWEAR_SERVICE_SIM_TRUTH_JSON_H_
#define ROLLWEAR_SERVICE_SIM_TRUTH_JSON_H_

#include <string>

#include "core/base/status.h"
#include "core/sim/simulator.h"

namespace rollwear {

// The truth as a pretty-printed JSON text (2-space indent, keys in a fixed
// order, non-finite numbers as null).
std::string TruthJson(const SimulationTruth& truth);

// Writes TruthJson(truth) to `path` (truncating it).
Status WriteTruthJson(const SimulationTruth& truth, const std::string& path);

}  // namespace rollwear

#endif  // ROLLWEAR_SERVICE_SIM_TRUTH_JSON_H_
