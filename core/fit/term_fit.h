// Joint fit of the baseline wear coefficients (option 1, log kF kR kS) and
// a set of model terms (model_terms.h), on per-pass data: the engine behind
// diagnosis. Unlike calibration.h it cannot reduce passes to sufficient
// statistics (a term may depend non-linearly on any pass quantity), so it
// keeps every pass of every measured (campaign, roll position) with the
// value of every catalogued covariate.
//
// Residuals are weighted: r_o = (y_o - yhat_o) / sd_o with sd_o from the
// baseline's noise model (wear_model.h), so that weighted RSS values of
// nested fits on the same observations give likelihood-ratio statistics
//   LR = n * ln(RSS_0 / RSS_1)  ~  chi-square(extra parameters).
//
// Thread-safety: TermData is immutable after BuildTermData; FitTerms and
// PredictTerms are reentrant.
#ifndef ROLLWEAR_CORE_FIT_TERM_FIT_H_
#define ROLLWEAR_CORE_FIT_TERM_FIT_H_

#include <memory>
#include <string>
#include <vector>

#include "core/model/aggregation.h"
#include "core/model/covariates.h"
#include "core/dataset/dataset.h"
#include "core/model/model_terms.h"
#include "core/base/status.h"
#include "core/model/wear_law.h"
#include "core/model/wear_model.h"

namespace rollwear {

// A measured roll (MountedRoll, aggregation.h) and its passes.
struct TermObservation : MountedRoll {
  int pass_begin = 0, pass_end = 0;  // range into the per-pass arrays
};

struct TermData {
  WearLaw law = WearLaw::kWang;
  std::vector<std::string> positions, roll_types, grades;
  std::vector<CovariateSpec> catalog;
  std::vector<TermObservation> obs;  // measured observations only
  std::vector<double> load;          // per pass: BaseLoad of the law
  std::vector<int> grade;            // per pass: grade level
  // [covariate][pass]; roll-, campaign- and measurement-level covariates
  // repeat their value on every pass of the observation.
  std::vector<std::vector<double>> z;
  // [covariate][observation]: the covariate campaign-aggregated as the
  // model aggregates it (load-weighted mean over the passes for pass-level
  // covariates, the value itself otherwise).
  std::vector<std::vector<double>> obs_z;
  // > 0 (and at least kMinShrunkGrades grades with load in a fit's subset):
  // the grade factors are shrunk as in calibration.h, log kS[s] ~ N(0,
  // grade_prior_sd^2), pseudo-residuals log kS[s] / grade_prior_sd (the
  // residuals are already divided by sd_o), no reference grade held fixed.
  // Set by the caller (BuildTermData leaves 0: grades fitted freely) to the
  // tau of option 1's calibration on the same training data.
  double grade_prior_sd = 0;
  int CovariateIndex(const std::string& name) const;  // -1 if unknown
};

StatusOr<TermData> BuildTermData(const Dataset& data, WearLaw law);

// A term being fitted: the term (its params are the start) and bounds.
struct TermSpec {
  ModelTerm term;
  int covariate = -1;  // index into TermData::catalog
  std::vector<double> lower, upper;  // per parameter
  // > 0: a normal prior b ~ N(0, prior_sd^2) on every parameter, added to
  // the fit as pseudo-residuals b / prior_sd (ridge shrinkage; cell terms,
  // docs/model.md). Its square enters weighted_rss (a penalised LR).
  double prior_sd = 0;
};

// The wear-coefficient part: log-coefficients of option 1 in the layout of
// KStructure::ForOption(1, positions, roll_types, grades).
struct TermFitResult {
  std::vector<double> log_k;
  std::vector<TermSpec> terms;  // with fitted params
  double weighted_rss = 0;
  bool usable = false;
  int iterations = 0;
  int num_free = 0;
  std::vector<double> term_std_error;  // per term parameter, concatenated
};

// Fits log_k and every term's parameters on observations `subset`
// (indices into data.obs) with per-observation sd `sd` (same indexing as
// data.obs). `log_k_start` may be empty (starts from the empirical set).
// With data.grade_prior_sd > 0 the grade factors carry their prior.
StatusOr<TermFitResult> FitTerms(const TermData& data, const std::vector<int>& subset,
                                 const std::vector<double>& sd,
                                 const std::vector<double>& log_k_start,
                                 const std::vector<TermSpec>& terms,
                                 bool compute_errors = false);

// Predicted measurement (wear plus measurement terms) of each observation
// in `subset`; with `wear_only`, the wear without measurement terms.
std::vector<double> PredictTerms(const TermData& data, const std::vector<int>& subset,
                                 const std::vector<double>& log_k,
                                 const std::vector<TermSpec>& terms,
                                 bool wear_only = false);

// Each pass's wear contribution k_g * load * prod_t m_t + sum_a a (the terms
// whose scope holds the pass) for the passes of the observations in `subset`,
// indexed like TermData::load (0 for the other passes). PredictTerms'
// wear_only value of an observation is the sum over its passes.
std::vector<double> PredictPassWear(const TermData& data, const std::vector<int>& subset,
                                    const std::vector<double>& log_k,
                                    const std::vector<TermSpec>& terms);

// Per-observation sd of every observation from the noise model
// sigma0^2 + (rho yhat)^2 (wear_model.h) fitted on the residuals of the
// training observations `train` under (log_k, terms); floored at 1e-6 µm.
// The weights of FitTerms that the diagnosis and the refit of adopted terms
// use. `noise_out` (optional) receives sigma0 and rho.
// With `robust` (robust.h): the noise model is fitted robustly and each
// sd_o is divided by sqrt(w_o), w_o the Huber weight of the observation's
// standardised residual, so that FitTerms, the score and likelihood-ratio
// tests and the cross-validation of the diagnosis run one IRLS step of
// Huber's loss at the current model's residuals (the weights are held fixed
// within a round, so nested fits stay comparable).
std::vector<double> TermNoiseSd(const TermData& td, const std::vector<int>& train,
                                const std::vector<double>& log_k,
                                const std::vector<TermSpec>& terms,
                                WearModel* noise_out = nullptr,
                                bool robust = true);

// Score (Lagrange-multiplier) test of adding `candidate` (at its start
// parameters; the parameters tested are those with a non-zero derivative,
// e.g. the amplitude b of a term whose length scale is held at the start)
// to the fitted model (log_k, terms) on `subset`:
//   S = r' Jc (Jc' Jc)^+ Jc' r / (r'r / n),  Jc = derivative columns of the
//   candidate with the current model's Jacobian projected out,
// asymptotically chi-square(df) under "no such term" (Rao 1948). It needs
// one pass over the data instead of a full refit, so the engine screens every
// candidate with it and refits only the strongest. Returns S and sets *df.
double ScoreStatistic(const TermData& data, const std::vector<int>& subset,
                      const std::vector<double>& sd, const std::vector<double>& log_k,
                      const std::vector<TermSpec>& terms, const TermSpec& candidate,
                      int* df);

// The score test of many candidates against one fitted model: the current
// model's weighted residuals, Jacobian and its QR decomposition, and each
// pass's wear contribution are computed once, so a candidate costs one pass
// over its own covariate. Statistic(c) equals ScoreStatistic(data, subset,
// sd, log_k, terms, c) exactly (same floating-point operations): a
// candidate at a start where its multiplier is exactly 1 and its reading
// offset exactly 0 (every null start of the diagnosis' library) leaves the
// current predictions and derivatives bit for bit as they are; any other
// start falls back to ScoreStatistic.
//
// Thread-safety: Statistic is const and may run concurrently; data, subset
// and sd must outlive the screen and not change.
class ScoreScreen {
 public:
  ScoreScreen(const TermData& data, const std::vector<int>& subset,
              const std::vector<double>& sd, const std::vector<double>& log_k,
              const std::vector<TermSpec>& terms);
  ~ScoreScreen();
  ScoreScreen(const ScoreScreen&) = delete;
  ScoreScreen& operator=(const ScoreScreen&) = delete;

  double Statistic(const TermSpec& candidate, int* df) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_TERM_FIT_H_
