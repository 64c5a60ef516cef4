// The study's Table 4 on any dataset: classical calibration (Wang's law,
// option 1, CalibrateOnSplit) against the recurrent K-estimator
// (ann_train.h) on the same seeded 2/3-1/3 campaign split as `calibrate`
// (SplitCampaigns), with training and validation gaps, the relative
// difference
//   delta % = 100 * (gap_ann - gap_classical) / gap_classical
// (negative = the ANN is better), the validation/training ratio of each
// model (overfitting shows as a ratio well above 1) and the spread of the
// ANN over its ensemble members (one seed each).
//
// Only the training campaigns are used to fit either model, the ANN's input
// scaling and its early stopping; validation campaigns are touched only to
// report figures.
//
// Thread-safety: CompareAnnWithClassical is reentrant.
#ifndef ROLLWEAR_CORE_ANN_ANN_STUDY_H_
#define ROLLWEAR_CORE_ANN_ANN_STUDY_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/model/ann_model.h"
#include "core/ann/ann_train.h"
#include "core/fit/calibration.h"
#include "core/fit/study.h"
#include "core/dataset/dataset.h"
#include "core/model/metrics.h"
#include "core/base/status.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct AnnComparisonOptions {
  uint64_t split_seed = kDefaultSplitSeed;
  // A split file's split (core/model/given_split.h); replaces the seeded one.
  std::optional<CampaignSplit> given_split;
  AnnTrainingOptions training;
  CalibrationOptions classical;  // default: Wang, option 1, empirical start
  // Also run the diagnosis (diagnosis.h, default options, same split seed)
  // and evaluate its adopted model on the same campaigns: the third row of
  // the comparison (docs/ann.md, "which model to pick").
  bool compare_adopted = false;
};

struct AnnMemberFigures {
  AnnMemberReport training;
  FitMetrics train;
  FitMetrics validation;
};

// The dataset and split (StudyDataset, study.h), then the figures.
struct AnnComparison : StudyDataset {
  // Classical calibration.
  FitMetrics classical_train, classical_val;
  double classical_bias_above_300_um = 0;  // mean (meas - pred), pred > 300 µm
  int n_above_300 = 0;
  int classical_parameters = 0;
  double classical_seconds = 0;
  // The ANN as served (ensemble mean or best member, per options).
  FitMetrics ann_train, ann_val;
  double ann_bias_above_300_um = 0;
  int ann_parameters = 0;  // weights per member
  std::string ann_mode;    // "ensemble mean of N members" / "best on holdout"
  // Every member alone, and the member with the best holdout cost.
  std::vector<AnnMemberFigures> members;
  int best_member = 0;
  double ann_seconds = 0;
  // The diagnosis's adopted model (option 1 plus terms), when asked for.
  bool has_adopted = false;
  FitMetrics adopted_train, adopted_val;
  int adopted_parameters = 0;
  std::vector<std::string> adopted_findings;  // "covariate (mechanism)"
  double adopted_seconds = 0;
  double seconds = 0;  // whole comparison
  AnnModel model;
};

StatusOr<AnnComparison> CompareAnnWithClassical(
    const Dataset& data, const AnnComparisonOptions& options);

// The comparison's split seen reading by reading: the Wang statistics the
// split is drawn on and the split (both as CompareAnnWithClassical drew
// them), and the trained ensemble's prediction of each measured reading of
// the training then the validation campaigns. For the figures and
// `ann --predictions`, which must score exactly the comparison's readings.
struct AnnSplitPredictions {
  WearStatistics stats;
  CampaignSplit split;
  std::vector<int> observations;     // measured: training, then validation
  std::vector<double> predicted_um;  // the ensemble mean, same order
  int num_train = 0;                 // the first num_train are training
};
StatusOr<AnnSplitPredictions> PredictAnnOnSplit(
    const Dataset& data, const AnnComparisonOptions& options,
    const AnnComparison& comparison);

// Mean and sample standard deviation of the members' validation (or
// training) gaps.
void MemberGapSpread(const AnnComparison& c, bool validation, double* mean,
                     double* sd, double* min, double* max);

// The network as a servable model (wear_model.h, WearModel::ann): trained on
// the training campaigns `train_campaigns` (campaign indices), with the
// noise model sigma0^2 + (rho d)^2 fitted on its training residuals so that
// the daemon can give an interval. What a calibration run with model "ann"
// promotes.
StatusOr<WearModel> TrainServableAnn(const Dataset& data,
                                     const std::vector<int>& train_campaigns,
                                     const AnnTrainingOptions& options);

// The Table 4 analogue as Markdown.
std::string AnnComparisonMarkdown(const AnnComparison& c);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_ANN_ANN_STUDY_H_
