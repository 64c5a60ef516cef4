// Whether a calibrated model is identified by its training data: the one
// judgement behind "usable" in `calibrate`, `study` and the daemon's
// promotion gate. A fit that converged is still not identified when
//   1. a coefficient sits at a bound of the solver (its value is the bound,
//      not the data's),
//   2. a coefficient's relative standard error exceeds 100 % (the standard
//      error of log k above 1: the data do not tell k from k·e), or
//   3. its validation gap exceeds what its own noise model allows: with p
//      free parameters fitted to n training readings, the mean |residual|
//      of new readings (each divided by its sd under the model's noise
//      model, FitMetrics::std_gap, where the model has one) is expected at
//      sqrt((n + p) / (n - p)) times the training one (least squares' optimism,
//      e.g. Hastie, Tibshirani & Friedman 2009, Elements of Statistical
//      Learning, Sec. 7.4); the ratio is refused when it lies more than z
//      = 3.09 (one-sided p = 0.001) above that, with the sd of a mean absolute
//      residual, sqrt(pi/2 - 1) / sqrt(m) relative to its mean for m normal
//      residuals, combined over the two sets.
// Shrunk grade factors (calibration.h) count in p by their effective number
// gamma. Coefficients without any training data (no load) are not counted: they
// are not used by any prediction on this data.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_FIT_IDENTIFICATION_H_
#define ROLLWEAR_CORE_FIT_IDENTIFICATION_H_

#include <string>
#include <vector>

#include "core/fit/calibration.h"
#include "core/model/metrics.h"

namespace rollwear {

struct Identification {
  bool identified = true;
  std::vector<std::string> at_bound;     // coefficient names
  std::vector<std::string> large_error;  // relative s.e. > 100 %
  double gap_ratio = 0;       // validation / training (standardised) gap
  double expected_ratio = 1;  // sqrt((n + p) / (n - p))
  double z = 0;               // (gap_ratio - expected) / sd of the ratio
  bool validation_beyond_noise = false;
  // "identified", or "not identified: 20 coefficients at a bound (kS[A],
  // kS[B], ...); 3 with relative s.e. > 100 % (...); validation gap 1.57 x
  // training, the noise model allows 1.17 (z = 9.8)".
  std::string Sentence() const;
};

// The z of criterion 3 at which a fit is refused.
inline constexpr double kIdentificationZ = 3.09;

// `extra_parameters`: what the fit spent beyond its free coefficients
// (the effective number of shrunk random effects: roll_effects.h), counted
// in p.
Identification JudgeIdentification(const CalibrationResult& result,
                                   const FitMetrics& train,
                                   const FitMetrics& validation,
                                   double extra_parameters = 0);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_IDENTIFICATION_H_
