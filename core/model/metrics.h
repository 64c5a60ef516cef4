// Figures of merit of the rollwear study and the campaign split they are
// computed on.
//
//   cost (study Eq. 9):  F = sum_p (1/n_p) sum_{c in p} (d_meas - d_calc)^2
//     p = roll position, n_p = number of campaigns measured at p
//   average wear gap:    mean |d_meas - d_calc|  (µm)
//
// The split is a seeded random 2/3 training / 1/3 validation split of the
// campaigns that have at least one measurement; every command (calibrate,
// study, ann, diagnose) uses the same split for the same seed.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_MODEL_METRICS_H_
#define ROLLWEAR_CORE_MODEL_METRICS_H_

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "core/model/aggregation.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct CampaignSplit {
  std::vector<int> train;       // campaign indices, ascending
  std::vector<int> validation;  // campaign indices, ascending
};

constexpr uint64_t kDefaultSplitSeed = 1;

CampaignSplit SplitCampaigns(const WearStatistics& stats,
                             double train_fraction = 2.0 / 3.0,
                             uint64_t seed = kDefaultSplitSeed);

// `given` when there is one (a split file: given_split.h), otherwise the
// seeded split: what every command splits on.
CampaignSplit SplitOrGiven(const WearStatistics& stats, uint64_t seed,
                           const std::optional<CampaignSplit>& given);

struct FitMetrics {
  double cost = 0;    // Eq. 9, µm^2
  double gap_um = 0;  // mean absolute difference, µm
  int n = 0;          // observations
  // Mean |difference| / sd under the model's own noise model (wear_model.h:
  // sd^2 = noise_sd_um^2 + (noise_rel * wear)^2); NaN when the model has
  // none (Evaluate fills it).
  double std_gap = std::numeric_limits<double>::quiet_NaN();
};

// Metrics of `model` on the measured observations `obs`.
FitMetrics Evaluate(const WearModel& model, const WearStatistics& stats,
                    const std::vector<int>& obs);

// Predicted centre wear of each observation in `obs`.
std::vector<double> PredictAll(const WearModel& model,
                               const WearStatistics& stats,
                               const std::vector<int>& obs);

// Eq. 9 cost and average gap of measured/predicted pairs, each with its
// roll position level: what Evaluate computes for any predictor.
FitMetrics MetricsOf(const std::vector<int>& position, const std::vector<double>& measured,
                     const std::vector<double>& predicted);

// Eq. 9 from measured/predicted pairs grouped by roll position level.
double PaperCost(const std::vector<int>& position, const std::vector<double>& measured,
                 const std::vector<double>& predicted);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_METRICS_H_
