// Internal to core/fit: the least-squares problem of Calibrate() and its
// stages. calibration.cc holds the problem (Fit), the Ceres side (solver
// set-up, solve, covariance) and Calibrate() itself, which runs the stages in
// order; calibration_stages.cc holds the stages that need no Ceres (input
// validation, option-2 prefit, initial set, gauge fixing, the grade
// shrinkage's evidence update, gauge transform, noise model). The cost, parameterisation, gauge and option-2 prior are
// described in calibration.h. Include only from core/fit/calibration*.cc.
//
// Thread-safety: a Fit belongs to one Calibrate() call and one thread; the
// stage functions share no state between calls.
#ifndef ROLLWEAR_CORE_FIT_CALIBRATION_INTERNAL_H_
#define ROLLWEAR_CORE_FIT_CALIBRATION_INTERNAL_H_

#include <vector>

#include <Eigen/Core>

#include "core/base/status.h"
#include "core/fit/calibration.h"
#include "core/model/aggregation.h"
#include "core/model/k_structure.h"
#include "core/model/wear_model.h"

namespace rollwear {
namespace calibration_internal {

// The full parameter vector theta: log k (n_coef), then for option 2 the
// prior surface u (roll types) and v (grades), then Cao's a.
struct Layout {
  int n_coef = 0;
  int u_offset = -1;
  int v_offset = -1;
  int a_index = -1;
  int n_full = 0;
  bool IsLog(int i) const { return i != a_index; }
};

// The weighted residuals of the training observations (study Eq. 9) and,
// for option 2, the prior rows, as a function of theta.
class Fit {
 public:
  Fit(const WearStatistics& stats, const std::vector<int>& train,
      const CalibrationOptions& options, KStructure structure);

  const Layout& layout() const { return layout_; }
  int num_rows() const { return num_rows_; }
  int num_data_rows() const { return static_cast<int>(train_.size()); }
  const KStructure& structure() const { return model_.structure; }
  const std::vector<double>& coef_load() const { return coef_load_; }
  void set_prior_scale(double lambda) { prior_scale_ = lambda; }
  // Grade shrinkage (calibration.h): the grade coefficients with a prior
  // row (empty when it does not apply) and its scale sigma / tau.
  const std::vector<int>& shrunk_grades() const { return shrunk_grades_; }
  double grade_scale() const { return grade_scale_; }
  void set_grade_scale(double lambda) { grade_scale_ = lambda; }
  long evaluations() const { return evaluations_; }

  // Residuals (size num_rows) and, when `jac` is non-null, the row-major
  // Jacobian d(residual)/d(theta) (num_rows x n_full) at theta.
  void Evaluate(const double* theta, double* residuals, double* jac);

  // Eq. 9 cost of the data rows of a residual vector (without the robust
  // weights).
  double DataCost(const std::vector<double>& residuals) const;

  // Robust loss: multiplies the residual of each data row by sqrt(w[row])
  // (w aligned with the training observations; all 1 at construction).
  void SetRobustWeights(const std::vector<double>& w);

  // The predictions and errors (measured - predicted, µm) of the data rows
  // behind a residual vector.
  void DataErrors(const std::vector<double>& residuals,
                  std::vector<double>* pred, std::vector<double>* err) const;

  // The model at the theta of the last Evaluate (every k = 1 before it).
  WearModel& model() { return model_; }
  const WearModel& model() const { return model_; }

 private:
  const WearStatistics& stats_;
  const std::vector<int>& train_;
  const CalibrationOptions& options_;
  WearModel model_;
  Layout layout_;
  int num_rt_ = 0, num_gr_ = 0, num_rows_ = 0;
  std::vector<double> eq9_weight_;    // 1/sqrt(n_p) per data row
  std::vector<double> robust_sqrt_;  // sqrt(Huber weight) per data row
  std::vector<double> weight_;       // their product
  std::vector<double> coef_load_;
  std::vector<double> grad_;
  double prior_scale_ = 0;
  std::vector<int> shrunk_grades_;
  double grade_scale_ = 0;
  long evaluations_ = 0;
};

// Stage 1. Rejects invalid options, statistics of another law and training
// indices that are out of range or have no measurement.
Status ValidateInputs(const WearStatistics& stats,
                      const std::vector<int>& train,
                      const CalibrationOptions& options);

// Stage 2 (option 2 only). The option-1 pre-fit with the empirical start;
// sets the fit's prior scale sigma_w / tau from its residual variance.
StatusOr<CalibrationResult> Option2Prefit(const WearStatistics& stats,
                                          const std::vector<int>& train,
                                          const CalibrationOptions& options,
                                          Fit* fit);

// Stage 3. The initial theta of options.initial_set; `prefit` (option 2) or
// null.
std::vector<double> InitialTheta(const WearStatistics& stats,
                                 const std::vector<int>& train,
                                 const CalibrationOptions& options,
                                 const Fit& fit,
                                 const CalibrationResult* prefit);

// Stage 4. Gauge and identifiability: the indices of theta left free.
std::vector<int> FreeParameters(const Fit& fit,
                                const CalibrationOptions& options);

// Stage 5b (grade shrinkage). One evidence update (calibration.h) at theta,
// the fit's residuals there and its current grade scale: the new tau and
// sigma and gamma. `free` are the solver's free parameters.
struct EvidenceUpdate {
  double tau = 0, sigma = 0, gamma = 0;
  bool ok = false;  // false when H cannot be inverted or is not finite
};
EvidenceUpdate UpdateGradeEvidence(Fit* fit, const std::vector<int>& free,
                                   const std::vector<double>& theta);

// Stage 7. The reported gauge: every non-position group has geometric mean
// 1 over its levels with data and kF carries the scale; theta_rep =
// T * theta with T (num_parameters x n_full) returned here.
Eigen::MatrixXd GaugeTransform(const Fit& fit);


// Stage 7. A copy of the fit's model at theta_rep = transform * theta.
WearModel ReportedModel(const Fit& fit, const Eigen::MatrixXd& transform,
                        const std::vector<double>& theta);

// Stage 9. The noise model of `model` fitted to its training residuals
// (robustly, robust.h, when `robust`).
void FitTrainingNoise(const WearStatistics& stats,
                      const std::vector<int>& train, bool robust,
                      WearModel* model);

}  // namespace calibration_internal
}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_CALIBRATION_INTERNAL_H_
