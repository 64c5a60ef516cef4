// Stage 1 of Diagnose() (diagnosis_stages_internal.h): the baseline, option
// 1 calibrated on the training campaigns, with its grade factors free where
// the data identify them and shrunk (core/fit/calibration.h) where they do
// not.
#include <string>
#include <utility>

#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/fit/identification.h"
#include "core/model/aggregation.h"

namespace rollwear::diag {

StatusOr<Baseline> RunBaseline(const Dataset& data,
                               const DiagnosisOptions& options,
                               DiagnosisReport* report) {
  const DatasetIndex index(data);
  ROLLWEAR_ASSIGN_OR_RETURN(WearStatistics stats,
                            Aggregate(data, index, options.law));
  Baseline base;
  base.split = SplitOrGiven(stats, options.split_seed, options.given_split);
  // The baseline's grade factors: free where the data identify them (the
  // diagnosis's tests were built and judged on that fit), shrunk
  // (calibration.h) where the free fit has a grade at a bound or a relative
  // s.e. above 100 %: rare grade codes.
  CalibrationOptions co;
  co.law = options.law;
  co.option = 1;
  co.robust = options.robust;
  co.shrink_grades = false;
  ROLLWEAR_ASSIGN_OR_RETURN(base.calibration,
                            CalibrateOnSplit(stats, base.split, co));
  const Identification free_id =
      JudgeIdentification(base.calibration.result, base.calibration.train,
                          base.calibration.validation);
  report->baseline_grades = "grades fitted freely";
  if (!free_id.at_bound.empty() || !free_id.large_error.empty()) {
    co.shrink_grades = true;
    // A shrunk fit that fails leaves the free one (and says so).
    StatusOr<SplitCalibration> shrunk = CalibrateOnSplit(stats, base.split, co);
    if (shrunk.ok() && shrunk->result.summary.usable &&
        shrunk->result.grade_shrinkage.applied) {
      report->baseline_grades = shrunk->result.grade_shrinkage.Sentence() +
                                ": the free fit is " + free_id.Sentence();
      base.calibration = *std::move(shrunk);
    } else {
      report->baseline_grades =
          "grades fitted freely (their shrunk fit failed): the free fit is " +
          free_id.Sentence();
    }
  }
  if (!base.calibration.result.summary.usable) {
    return Status::NumericalFailure(
        "baseline calibration failed: " +
        base.calibration.result.summary.BriefReport());
  }
  report->baseline_gap_train_um = base.calibration.train.gap_um;
  report->baseline_gap_val_um = base.calibration.validation.gap_um;
  return base;
}

}  // namespace rollwear::diag
