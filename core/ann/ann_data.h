// The inputs of the recurrent K-estimator (ann_model.h) for a whole dataset:
// every (campaign, roll position) observation of a WearStatistics becomes a
// sequence of scaled pass inputs in rolling order, with the Wang load of each
// pass. Also the batch prediction and figures of merit of an AnnModel on
// such sequences - the same figures (average wear gap, Eq. 9 cost) as
// metrics.h computes for the classical models.
//
// The input scaling is fitted on the passes of training campaigns only:
//   mean_j = mean of x_j,  sd_j = standard deviation of x_j (1 if 0)
// and for the wear-state input, from the training measurements m (µm):
//   mu_W = mean(m) / 2,  sd_W = sqrt(mean(m^2) / 3 - mu_W^2)
// which are the mean and sd of W = t * m for t uniform on [0, 1] (the wear
// along a campaign grows from 0 to m, roughly linearly).
//
// Thread-safety: AnnInputs is immutable after BuildAnnInputs; the functions
// are reentrant.
#ifndef ROLLWEAR_CORE_ANN_ANN_DATA_H_
#define ROLLWEAR_CORE_ANN_ANN_DATA_H_

#include <vector>

#include <Eigen/Core>

#include "core/model/aggregation.h"
#include "core/model/ann_model.h"
#include "core/dataset/dataset.h"
#include "core/model/metrics.h"
#include "core/base/status.h"

namespace rollwear {

struct AnnSequence {
  int observation = -1;  // index into WearStatistics::observations
  int campaign = -1;     // index into Dataset::campaigns
  int position = -1;     // position level of the WearStatistics (Eq. 9)
  bool measured = false;
  double measured_um = 0;
  Eigen::VectorXd static_input;  // scaled, size AnnModel::num_static()
  int begin = 0;  // range of columns of AnnInputs::pass_input and load
  int end = 0;
};

struct AnnInputs {
  Eigen::MatrixXd pass_input;  // AnnModel::num_pass() x passes, scaled
  Eigen::VectorXd load;        // Wang BaseLoad of each pass
  // One per WearStatistics observation, same order.
  std::vector<AnnSequence> sequences;
};

// A model without members: the labels of `stats` (Wang statistics of
// `data`) that occur in `train_campaigns` (others are treated as unknown
// labels) and the input scaling fitted on those campaigns' passes.
StatusOr<AnnModel> FitAnnScaling(const Dataset& data, const DatasetIndex& index,
                                 const WearStatistics& stats,
                                 const std::vector<int>& train_campaigns,
                                 int hidden1, int hidden2);

// Encodes every observation of `stats` with the model's labels and scaling.
AnnInputs BuildAnnInputs(const AnnModel& model, const Dataset& data,
                         const DatasetIndex& index,
                         const WearStatistics& stats);

// Average wear gap and Eq. 9 cost of the measured sequences `seqs` under the
// given predictions (same order).
FitMetrics AnnMetrics(const AnnInputs& inputs, const std::vector<int>& seqs,
                      const std::vector<double>& predicted);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_ANN_ANN_DATA_H_
