// Per-roll wear resistance: every physical roll (roll_id) gets its own
// multiplier of the wear law, a random effect shrunk towards its roll type,
// with the spread estimated from the data (empirical Bayes), never a free
// parameter per roll.
//
// Model, for reading i of roll r (its campaign's centre wear):
//   y_i = m_r * x_i + e_i,   e_i ~ N(0, sigma_i^2),   m_r ~ N(1, tau^2)
//   sigma_i^2 = sigma0^2 + (rho * x_i)^2
// (grinder noise plus a part that grows with the wear; sigma0, rho from the
// within-roll residuals, least squares of e^2 on [1, x^2] scaled by
// n / (n - R), alternated with the weighted fits below three times).
// where x_i is the wear law's prediction with K of the K structure (the
// roll type's coefficient included, so m_r = 1 is "as its roll type").
// Given K, each roll's weighted least-squares multiplier and its variance
// are (w_i = 1 / sigma_i^2)
//   mhat_r = sum w x y / sum w x^2,   v_r = 1 / sum w x^2;
// tau^2 is the DerSimonian & Laird (1986, Controlled Clinical
// Trials 7:177) moment estimate of the between-roll variance of mhat_r
//   Q = sum w_r (mhat_r - mbar)^2,  w_r = 1/v_r,
//   tau^2 = max(0, (Q - (R - 1)) / (sum w - sum w^2 / sum w));
// and each roll's multiplier is its posterior mean and variance under the
// normal prior (Morris 1983, JASA 78:47, parametric empirical Bayes)
//   m_r = (mhat_r / v_r + 1 / tau^2) / (1 / v_r + 1 / tau^2)
//   s_r^2 = 1 / (1 / v_r + 1 / tau^2) + B_r^2 var(mbar),
// B_r = (1 / tau^2) / (1 / v_r + 1 / tau^2) the roll's shrinkage and
// var(mbar) = 1 / sum 1 / (v_r + tau^2) the uncertainty of the centre it
// is shrunk to (Morris 1983's estimated-mean correction).
// K is then refitted with every reading's prediction scaled by its roll's
// m_r, and the two steps alternate until the multipliers move less than
// 1e-3 (backfitting). A roll without training readings gets m = 1 with
// sd tau (a new roll starts at its type's value).
//
// A reading's 95 % prediction interval: m_r x +- 1.96 sqrt(sigma_i^2 +
// x^2 s_r^2) (K's own uncertainty is not included). The prior is centred
// on the rolls' weighted mean mbar, and every multiplier is reported
// divided by it (K takes the level).
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_FIT_ROLL_EFFECTS_H_
#define ROLLWEAR_CORE_FIT_ROLL_EFFECTS_H_

#include <string>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/fit/calibration.h"
#include "core/model/aggregation.h"
#include "core/model/metrics.h"

namespace rollwear {

struct RollEffect {
  std::string roll_id;
  int readings = 0;  // training readings of this roll
  double raw = 1;    // mhat_r, the roll's own least-squares multiplier
  double value = 1;  // m_r, shrunk
  double sd = 0;     // s_r, posterior sd
};

struct RollEffects {
  double tau = 0;  // between-roll sd of the multiplier
  // Effective number of parameters the multipliers add: sum over rolls of
  // info / (info + 1 / tau^2), the trace of the shrinkage (0 when tau = 0).
  double effective_parameters = 0;
  // Within-roll noise: var = sigma_um^2 + (noise_rel * x)^2.
  double sigma_um = 0;
  double noise_rel = 0;
  int iterations = 0;  // backfitting rounds
  bool converged = false;
  std::vector<RollEffect> rolls;  // ordered by roll_id
  // The multiplier and its sd of a roll (1 and tau when it has no
  // training reading).
  double ValueOf(const std::string& roll_id) const;
  double SdOf(const std::string& roll_id) const;
  std::unordered_map<std::string, int> index;  // roll_id -> rolls[i]
};

struct RollEffectsFit {
  CalibrationResult result;  // K given the multipliers
  RollEffects effects;
  FitMetrics train, validation;
  // Per observation of stats: the multiplier of its roll (1 unmeasured).
  std::vector<double> multiplier;
};

// Calibrates K (options) jointly with the per-roll multipliers on the
// training readings of `split`, evaluates both sets.
StatusOr<RollEffectsFit> CalibrateWithRollEffects(
    const Dataset& data, const WearStatistics& stats,
    const CampaignSplit& split, const CalibrationOptions& options);

// `stats` with every observation's load scaled by multiplier[o] (Wang,
// Nikitenko: the grade sums; Cao: its passes' base loads).
WearStatistics ScaledStatistics(const WearStatistics& stats,
                                const std::vector<double>& multiplier);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_ROLL_EFFECTS_H_
