// A physical roll's own wear factor updated by its readings, as the daemon
// keeps it between calibrations: when a roll's campaign is measured, the
// roll's level of the served model's roll-effect term (model_terms.h,
// TermForm::kRollEffect) is re-estimated from every plausible reading of
// that roll, given the rest of the model (K and the other terms) as they
// are. A roll without readings stays at its type's value, exp(0) = 1, with
// the prior's sd.
//
// Model, for reading i of the roll (its campaign's centre wear):
//   y_i = x_i exp(b) + o_i + e_i,   e_i ~ N(0, s_i^2),   b ~ N(0, tau^2)
// where x_i is the wear predicted for that campaign without the roll's own
// factor, o_i the model's measurement terms (the reading's offset), s_i the
// model's noise at the roll type's prediction,
// s_i^2 = sigma0^2 + (rho x_i)^2 (wear_model.h), and tau the term's prior
// sd (ModelTerm::scale, the between-roll spread the calibration
// estimated). This is the roll-effect term's own likelihood with its prior
// row (term_refit.cc: the pseudo-residual b / tau), with K and every other
// term held fixed. The weights do not move with b: the objective
//   F(b) = sum_i (y_i - o_i - x_i e^b)^2 / (2 s_i^2) + b^2 / (2 tau^2)
// is then a penalised weighted least-squares criterion whose minimum always
// exists (a noise growing with e^b has none for a reading at or below its
// offset when sigma0 = 0), and it depends only on the readings' x_i, o_i,
// y_i, so re-estimating from any state gives the same factor.
//
// F need not be convex in b (x e^b), so its minimum is found globally: F
// on a grid of step 0.02 over b in [-6, 6] (factors 0.0025..403), then a
// golden-section search (Kiefer 1953, Proc. AMS 4:502) between the best
// grid point's neighbours to 1e-10, polished by Newton steps on F'(b) = 0.
// A minimum at the grid's edge is not
// converged: the caller keeps what it had. The sd is the Gauss-Newton one
// (the expected information, as the term fits' level_sd, term_refit.cc):
// 1 / sqrt(sum_i (x_i e^b)^2 / s_i^2 + 1 / tau^2) at the mode. K's own
// uncertainty is not included, as in the calibration's per-roll intervals
// (roll_effects.h).
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_MODEL_ROLL_FACTOR_UPDATE_H_
#define ROLLWEAR_CORE_MODEL_ROLL_FACTOR_UPDATE_H_

#include <string>
#include <vector>

#include "core/model/model_terms.h"

namespace rollwear {

// One measured campaign of the roll (see the header comment).
struct RollReading {
  double base_um = 0;      // x_i: predicted wear without the roll's factor
  double offset_um = 0;    // o_i: the model's measurement terms
  double measured_um = 0;  // y_i
};

// The model's noise: s^2 = sd_um^2 + (rel * wear)^2 (wear_model.h), taken
// at the roll type's prediction x_i.
struct ReadingNoise {
  double sd_um = 0;
  double rel = 0;
};

struct RollFactorPosterior {
  double log_factor = 0;  // b_hat
  double log_sd = 0;      // its posterior sd
  int readings = 0;       // readings used (finite, x_i > 0)
  // false when the minimum lies beyond the grid (b at -6 or 6): the
  // readings cannot be those of a roll of this type, and the estimate is
  // not to be used.
  bool converged = true;
};

// The posterior of b under prior N(0, prior_sd^2) and `readings`; with no
// usable reading, a noise model of zero, or prior_sd <= 0, the prior
// itself: b = 0, sd = prior_sd.
RollFactorPosterior RollFactorPosteriorOf(
    double prior_sd, ReadingNoise noise,
    const std::vector<RollReading>& readings);

// The model's roll-effect term (nullptr when it has none).
const ModelTerm* RollEffectTermOf(const std::vector<ModelTerm>& terms);
ModelTerm* RollEffectTermOf(std::vector<ModelTerm>* terms);

// The log factor b_r a roll-effect term gives `roll_id` (0: a roll the term
// does not know counts as its type's value).
double RollLogFactor(const ModelTerm& term, const std::string& roll_id);

// Sets the roll's level of `term` to `posterior` (value, sd and readings),
// adding the level when the term does not know the roll yet.
void SetRollLevel(const std::string& roll_id,
                  const RollFactorPosterior& posterior, ModelTerm* term);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_ROLL_FACTOR_UPDATE_H_
