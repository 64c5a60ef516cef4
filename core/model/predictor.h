// Incremental, coil-by-coil wear prediction for one mounted roll: the state
// the daemon keeps per roll position. Each pass adds
//   wear_i = K(p, r, s_i) * Load(law, pass_i, roll) * m_i + added_i
// (m_i the wear-rate terms' product, added_i the additive terms' wear:
// model_terms.h) and the running gradient in K's parameters with respect to the
// model parameters, so the prediction interval (wear_model.h) is available at
// any moment. Summing the passes one by one gives the batch prediction of
// PredictObservation() on the same data up to rounding (tests check 1e-9
// relative).
//
// Labels unknown to the model (a new roll type or grade) use the gauge
// value 1 for that factor, i.e. the geometric mean of the known levels.
//
// Adopted terms on a mill's extra columns take their value from the extra
// fields of the records (ExtraFields: the pass's and its coil's in
// PassInput::extra, the roll's and the campaign's in RollWearState), found
// by the column's name in that order. A field a record lacks is an empty
// cell, as in the batch path (covariates.h): a numeric term then counts as
// 1 (NaN), a per-level term takes the empty text's level. A factor level is
// matched by its label (ModelTerm::levels); a label the fit never saw
// counts as 1, as a level without training data does in the batch path.
// A roll-effect term takes the multiplier of the mounted roll's id
// (RollWearState::roll_id); a roll it never saw counts as 1, its type's
// value. A scoped term (ModelTerm::scope) counts as 1 outside its scope: the
// roll's stand, position and roll type label, the pass's grade label.
//
// The wear profile across the barrel (barrel_profile.h), when tracked
// (TrackProfile): each pass also adds its wear to the roll's ProfileStats,
// the six per-slice sums from which the profile of any shape is read, at
// the strip's place by the shift convention (StripCentreMm, width_mm / 2).
// The sums do not depend on the shape, so a new shape needs no replay. The
// update is the one core/fit/profile_fit.cc makes per pass, so the state
// after N passes equals the batch sums exactly; it costs about 1 µs per
// pass (the slices under the strip, six basis values each).
//
// When the model is the recurrent network (WearModel::ann), the same calls
// run the network coil by coil (ann_model.h): the state then carries the
// network's per-member recurrence and the interval combines the members'
// spread with the noise model.
//
// Thread-safety: RollWearState (roll_wear_state.h) is a plain value;
// callers serialise updates of one state. The model is only read.
#ifndef ROLLWEAR_CORE_MODEL_PREDICTOR_H_
#define ROLLWEAR_CORE_MODEL_PREDICTOR_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"
#include "core/dataset/pass_input.h"
#include "core/model/barrel_profile.h"
#include "core/model/roll_wear_state.h"
#include "core/model/wear_law.h"
#include "core/model/wear_model.h"

namespace rollwear {

// A freshly mounted roll at `position_label` ("F6/top"); `roll_id` is
// the physical roll's serial, matched by a roll-effect term.
RollWearState MountRoll(const WearModel& model, const std::string& position_label,
                        const std::string& roll_type, double diameter_mm,
                        double hardness_hb, UnixSeconds campaign_started_at = 0,
                        ExtraFields mount_extra = {},
                        ExtraFields campaign_extra = {},
                        std::string roll_id = {});

// Starts tracking the state's profile on `grid` (empty sums: call it at
// mount, before the first pass).
void TrackProfile(RollWearState* state, const ProfileGrid& grid = {});

// Product of the model's wear-rate terms for this pass on this roll (1 when
// the model has none): the covariates come from the pass, the roll and the
// roll's state before the pass (campaign_length_before_m = rolled length so
// far, campaign_coils_before = coils so far), and the extra fields of the
// pass, the roll and the campaign (see above).
double PassTermMultiplier(const WearModel& model, const PassInput& pass,
                          const RollWearState& state);

// The wear-rate terms' product (PassTermMultiplier) and the additive
// terms' wear in µm (model_terms.h: wear per coil, times the roll's own
// factor) for this pass on this roll; the pass's wear is the law's times
// `multiplier` plus `added_um`.
struct PassTermEffect {
  double multiplier = 1.0;
  double added_um = 0.0;
};
PassTermEffect PassTermEffects(const WearModel& model, const PassInput& pass,
                               const RollWearState& state);

// Adds one pass; returns the wear increment in µm.
double AddPass(const WearModel& model, const PassInput& pass, RollWearState* state);

// 95 % prediction interval of the state's wear.
std::pair<double, double> WearInterval(const WearModel& model,
                                       const RollWearState& state);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_PREDICTOR_H_
