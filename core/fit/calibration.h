// Calibration of the wear coefficients K with Levenberg-Marquardt (Ceres)
// on per-campaign sufficient statistics (aggregation.h).
//
// Minimised cost (study Eq. 9), over the training observations:
//   F = sum_p (1/n_p) sum_{c in p} (d_meas[c,p] - d_calc[c,p])^2
// as Ceres residuals r = (d_meas - d_calc) / sqrt(n_p).
//
// Exact mode (default): parameters are log k (positivity by construction),
// analytic Jacobian, bounds |log k| <= log_bound and a in [a_lo, a_hi] for
// Cao; one reference level per non-position group is held fixed (gauge, see
// k_structure.h) and the result is reported in the geometric-mean gauge.
// Paper mode: the study's protocol - natural k with bounds, forward
// differences with relative step 5e-3, at most 10*n evaluations - on the
// same cost, gauge and priors, so the two can be compared.
//
// Option 2 shrinkage: rare or absent (roll type, grade) cells must not give
// wild coefficients, so log kRS[r,s] gets a Gaussian prior centred on an
// additive (option-1-like) surface u_r + v_s with sd `option2_prior_sd`:
//   extra residuals  (sigma_w / tau) * (log kRS[r,s] - u_r - v_s)
// where sigma_w^2 is the weighted residual variance of an option-1 pre-fit.
// Cells with no data then take the option-1 value u_r + v_s.
//
// Grade shrinkage (options.shrink_grades, exact mode, option 1 with at
// least kMinShrunkGrades grades carrying training load): the grade factors
// are a random effect, log kS[s] ~ N(0, tau^2) independently, so that a grade
// seen on a few campaigns is pulled toward the typical grade instead of
// being fitted freely (or driven to a bound):
//   extra residuals  (sigma / tau) * log kS[s]   for every grade with load,
// and no reference grade is held fixed (the prior fixes that gauge; the
// result is reported in the usual gauge). sigma and tau come from the data by
// the evidence approximation (MacKay 1992, "Bayesian interpolation", Neural
// Computation 4:415, Eqs. 4.9-4.10), alternated with the fit: with H = J'J
// (J the Jacobian of all residual rows, prior rows included, over the free
// parameters) and lambda = sigma / tau,
//   gamma   = sum_s (1 - lambda^2 [H^-1]_ss)     grade factors the data fix
//   tau^2   = sum_s (log kS[s])^2 / gamma
//   sigma^2 = RSS_data / (m - (p - G) - gamma)
// (m training readings, p free parameters of which G grades), until tau moves
// under 1 %, at most kMaxShrinkageRounds rounds. tau floors at 1e-3 (every
// grade pooled). The identification verdict counts p - G + gamma parameters.
// Options 2 and 3 and the study's protocol are unchanged (the study sets
// shrink_grades = false to reproduce the paper's fits).
//
// Robust loss (options.robust, exact mode only; robust.h): after the
// least-squares solve, two IRLS steps with Huber weights w_i (k = 3 sd's of
// the robust noise model of the training residuals, re-estimated at each
// step) multiply each residual by sqrt(w_i) and re-solve from the previous
// optimum, so a few gross grinder errors carry bounded influence. The
// reported costs stay Eq. 9 (unweighted by w). The study's protocol and the
// NIST checks keep least squares.
//
// Standard errors: Ceres covariance (dense SVD, rank deficiency handled by a
// pseudo-inverse) of the free parameters, scaled by s^2 = sum r^2/(m - n),
// mapped to the reported gauge. With the robust loss, r and the Jacobian
// carry the final IRLS weights: the weighted-least-squares covariance
// s_w^2 (J' W J)^-1 of the last IRLS step (Street, Carroll & Ruppert 1988,
// Am. Stat. 42:152), which for k = 3 differs from Huber's asymptotic
// sandwich (Huber & Ronchetti 2009, sec. 7.6) by under 1 % on Gaussian data.
//
// Thread-safety: Calibrate is reentrant; it shares no state between calls.
#ifndef ROLLWEAR_CORE_FIT_CALIBRATION_H_
#define ROLLWEAR_CORE_FIT_CALIBRATION_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/model/aggregation.h"
#include "core/fit/lm_options.h"
#include "core/base/status.h"
#include "core/model/wear_model.h"

namespace rollwear {

// The study's three initial sets.
enum class InitialSet {
  kOnes = 1,       // every coefficient 1 (a = 1 for Cao)
  kRandom = 2,     // one random value per factor group (seeded)
  kEmpirical = 3,  // kF[p] = sum d_meas / sum load per position, others 1
};
const char* InitialSetName(InitialSet s);  // "ones", "random", "empirical"

enum class DerivativeMode {
  kExact,                   // analytic Jacobian, log parameters
  kPaperForwardDifference,  // the study's protocol
};

struct CalibrationOptions {
  WearLaw law = WearLaw::kWang;
  int option = 1;
  InitialSet initial_set = InitialSet::kEmpirical;
  uint64_t seed = 1;  // for InitialSet::kRandom
  DerivativeMode derivatives = DerivativeMode::kExact;
  double fd_relative_step = 5e-3;          // paper mode
  int max_evaluations_per_parameter = 10;  // paper mode: at most 10*n
  double log_bound = 10;                   // |log k| <= log_bound
  double paper_k_lower = 1e-6;             // paper mode bounds on k
  double paper_k_upper = 1e4;
  double cao_a_lower = 0.2;
  double cao_a_upper = 4.0;
  double option2_prior_sd = 0.3;  // tau, log scale
  bool compute_covariance = true;
  // Huber IRLS after the least-squares solve (exact mode; see above). The
  // study (study.h) sets it false to reproduce the paper's least squares.
  bool robust = true;
  // Option 1's grade factors as a random effect (see above). Exact mode.
  bool shrink_grades = true;
  LmOptions lm;

  bool IsValid(std::string* error) const;
};

struct CalibrationSummary {
  bool usable = false;      // converged (or hit the budget) to finite values
  std::string termination;  // Ceres termination type, e.g. "CONVERGENCE"
  std::string message;
  int iterations = 0;
  int evaluations = 0;  // residual evaluations (incl. finite differences)
  int num_free_parameters = 0;
  int num_observations = 0;
  double initial_cost = 0;  // Eq. 9 on training, µm^2
  double final_cost = 0;
  double seconds = 0;
  // One line: "wang option 1: CONVERGENCE after 7 iterations, cost 1234 ->
  // 567 µm^2, 21 parameters, 1053 observations, usable".
  std::string BriefReport() const;
};

// Grade shrinkage (see above): fewer grades with training load than this
// are fitted freely. The most rounds of the evidence update.
inline constexpr int kMinShrunkGrades = 3;
inline constexpr int kMaxShrinkageRounds = 20;

// What the grade shrinkage did; `applied` false when it did not run.
struct GradeShrinkage {
  bool applied = false;
  int levels = 0;          // G, grades with training load
  double tau = 0;          // between-grade sd of log kS
  double sigma = 0;        // residual sd (Eq. 9 scale)
  double effective_parameters = 0;  // gamma
  int rounds = 0;          // evidence updates
  bool converged = false;  // tau moved under 1 % in the last round
  // "114 grades shrunk toward the typical grade (random effect, tau = 0.21
  // on log kS, 31.4 effective parameters)", or "grades fitted freely".
  std::string Sentence() const;
};

struct CalibrationResult {
  WearModel model;
  CalibrationSummary summary;
  // Per parameter of model (log k..., a): standard error in the reported
  // gauge; NaN where the training data do not identify it.
  std::vector<double> std_error;
  std::vector<bool> identified;
  // Per parameter of model: the solution sits at one of its bounds
  // (|log k| = log_bound, a paper-mode k or Cao's a at its limit); its
  // standard error is then not meaningful (identification.h).
  std::vector<bool> at_bound;
  // Robust loss: the final Huber weight of each training observation
  // (aligned with `train`; empty without the robust loss).
  std::vector<double> robust_weight;
  GradeShrinkage grade_shrinkage;
};

// Calibrates on the observations `train` (indices into
// stats.observations, each with a measurement). A fit that fails
// numerically is returned with summary.usable = false; a Status error means
// the inputs were unusable (invalid options, no training data).
StatusOr<CalibrationResult> Calibrate(const WearStatistics& stats,
                                      const std::vector<int>& train,
                                      const CalibrationOptions& options);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_CALIBRATION_H_
