// The engine's predictor for the store (storage/wear_predictor.h): the
// mounted rolls' states, each pass's wear, a reading's measurement terms
// and the per-roll factors, computed with core's model
// (core/model/predictor.h, model_eval.h, roll_factor_update.h). The store
// calls it inside its commits and replays; every store is opened through
// OpenStore, which hands it this predictor.
//
// Thread-safety: the predictor is stateless and shared; OpenStore may be
// called from any thread.
#ifndef ROLLWEAR_ENGINE_WEAR_PREDICTION_H_
#define ROLLWEAR_ENGINE_WEAR_PREDICTION_H_

#include <memory>
#include <string>

#include "core/base/status.h"
#include "storage/mill_store.h"
#include "storage/wear_predictor.h"

namespace rollwear::engine {

// The predictor every store of the daemon and the tools uses.
std::shared_ptr<const storage::WearPredictor> CoreWearPredictor();

// `options` with the engine's predictor.
storage::StoreOptions WithPredictor(storage::StoreOptions options);

// Opens (creating or migrating) the store at `path` with `options` and the
// engine's predictor (storage::MillStore::Open).
StatusOr<std::unique_ptr<storage::MillStore>> OpenStore(
    const std::string& path,
    const storage::StoreOptions& options = storage::StoreOptions());

}  // namespace rollwear::engine

#endif  // ROLLWEAR_ENGINE_WEAR_PREDICTION_H_
