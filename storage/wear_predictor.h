// WearPredictor: the predictions the store needs as it commits and replays,
// supplied by the engine (engine/wear_prediction.h, which runs core's
// model: core/model/predictor.h, model_eval.h, roll_factor_update.h). The
// store keeps the mounted rolls' states and each coil's answer with its
// commit (a coil's answer is durable with the coil), so its writer calls
// the predictor inside the commit; it never computes a prediction itself
// (.ci/check_layers.sh refuses those core headers in storage).
//
// What the store asks: a roll's state when it is mounted, one pass added
// to it, what the model's measurement terms add to a reading (the
// grinder's expected reading is the predicted wear plus it), a roll's
// predicted profile at a grinder's points, and the
// per-roll family's factors re-estimated from the readings (served from a
// reading's commit on). The store chooses the campaigns and replays them;
// the predictor does the model's arithmetic.
//
// Thread-safety: implementations are stateless; every method is const and
// may be called from any thread at once (the writer and the readers' replays).
#ifndef ROLLWEAR_STORAGE_WEAR_PREDICTOR_H_
#define ROLLWEAR_STORAGE_WEAR_PREDICTOR_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"
#include "core/dataset/pass_input.h"
#include "core/model/barrel_profile.h"
#include "core/model/model_terms.h"
#include "core/model/reading_context.h"
#include "core/model/roll_wear_state.h"
#include "core/model/wear_model.h"
#include "storage/store_types.h"

namespace rollwear::storage {

// One reading of a roll for its own factor: the wear predicted without the
// roll's factor, the measurement terms' offset, and what was read.
struct RollFactorReading {
  double base_um = 0;
  double offset_um = 0;
  double measured_um = 0;
};

class WearPredictor {
 public:
  virtual ~WearPredictor() = default;

  // The state of `roll` mounted under `model` for a campaign started at
  // `started_at` with the extra fields `campaign_extra`; with
  // `track_profile` its profile sums are kept too (the live rolls', the
  // dashboard's profiles).
  virtual RollWearState Mount(const WearModel& model, const MountedRollIn& roll,
                              UnixSeconds started_at,
                              const ExtraFields& campaign_extra,
                              bool track_profile) const = 0;
  // Adds one pass to `state`; the pass's wear in µm.
  virtual double AddPass(const WearModel& model, const PassInput& pass,
                         RollWearState* state) const = 0;
  // What the model's measurement terms add to `reading`, µm.
  virtual double ReadingOffset(const WearModel& model,
                               const ReadingContext& reading) const = 0;
  // The per-roll term readings re-estimate: none (nullptr) without one,
  // for the network, or for one scoped by grade (it acts on some passes
  // only, so the prediction over the factor is not the roll's wear).
  virtual const ModelTerm* UpdatableRollTerm(const WearModel& model) const = 0;
  // The log factor `term` gives `roll_id` (0 for a roll it does not know).
  virtual double RollLogFactor(const ModelTerm& term,
                               const std::string& roll_id) const = 0;
  // The wear a roll's tracked profile sums predict at each of `x_mm` with
  // the profile shape `shape` (the slices' values read at each point); empty
  // when `state` tracks no profile (the network's model).
  virtual std::vector<double> ProfileAt(
      const RollWearState& state, const ProfileShape& shape,
      const std::vector<double>& x_mm) const = 0;
  // `model` with the factor of each roll in `readings` re-estimated from
  // them; a roll whose readings no factor of its type explains keeps its
  // level.
  virtual WearModel WithRollFactors(
      const WearModel& model,
      const std::map<std::string, std::vector<RollFactorReading>>& readings)
      const = 0;
};

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_WEAR_PREDICTOR_H_
