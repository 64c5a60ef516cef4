// Recalibration of a model with adopted terms (diagnosis.h): the option-1
// wear coefficients and the parameters of every adopted term refitted
// jointly by Levenberg-Marquardt (term_fit.h) on the training campaigns,
// with the terms' form, covariate, centring and bins kept as adopted. This is
// what the nightly recalibration and `rollwear calibrate --terms` run once a
// finding has become part of the model, so the adopted physics is not lost
// when K is updated.
//
// Weights: a first fit with unit weights gives residuals whose robust noise
// model sigma0^2 + (rho d)^2 and Huber weights (robust.h, TermNoiseSd) set
// sd_o for a second, weighted fit, and that fit's for a third: the Huber
// loss the diagnosis used when it adopted the terms.
//
// The model's noise model is the last pass's, widened to cover the
// training readings' tails (robust.h, TailCoverageScale).
//
// Grades: shrunk toward the typical grade (term_fit.h's grade prior) with
// the between-grade sd tau of option 1's calibration on the same training
// campaigns (calibration.h), where that calibration shrinks them.
//
// Thread-safety: pure function of its arguments.
#ifndef ROLLWEAR_CORE_FIT_TERM_REFIT_H_
#define ROLLWEAR_CORE_FIT_TERM_REFIT_H_

#include <vector>

#include "core/dataset/dataset.h"
#include "core/fit/term_fit.h"
#include "core/model/model_terms.h"
#include "core/base/status.h"
#include "core/model/wear_law.h"
#include "core/model/wear_model.h"

namespace rollwear {

// Fits on the measured rolls of `train_campaigns` (campaign indices). The
// returned model has option-1 structure over the dataset's levels, the
// refitted terms and a noise model from the training residuals (no
// coefficient covariance). InvalidArgument when a term's covariate is not
// in the dataset; NumericalFailure when the fit is unusable.
StatusOr<WearModel> RefitWithTerms(const Dataset& data, WearLaw law,
                                   const std::vector<ModelTerm>& terms,
                                   const std::vector<int>& train_campaigns);

// Fills level_sd and level_readings of every roll-effect term of `terms`
// from the readings of `subset` (indices into td.obs) under (log_k,
// terms) with noise sd `sd` (indexed like td.obs): per roll r, the
// Gaussian posterior sd of b_r given K,
//   sd_r = (sum_i (yhat_i / sd_i)^2 + 1 / prior_sd^2)^(-1/2),
// d yhat_i / d b_r = yhat_i for every reading of roll r (model_terms.h:
// m = exp(b_r) scales all its passes; a measurement offset is ignored).
void SetRollEffectSpread(const TermData& td, const std::vector<int>& subset,
                         const std::vector<double>& sd,
                         const std::vector<double>& log_k,
                         std::vector<TermSpec>* terms);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_TERM_REFIT_H_
