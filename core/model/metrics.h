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

struct FitMetrics {
  double cost = 0;    // Eq. 9, µm^2
  double gap_um = 0;  // mean absolute difference, µm
  int n = 0;          // observations
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
