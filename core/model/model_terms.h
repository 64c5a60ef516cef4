// Model terms: physics the baseline wear law leaves out, as nested
// extensions that reduce to the baseline when their parameters are zero.
//
// Wear-rate terms multiply the wear of every pass i of a roll:
//   w_i = K * Load_i * prod_t m_t(z_t,i)
//   log-linear   m = exp(b * (z - c) / s)          c, s: training mean, sd
//   power        m = (z / c)^b                     z > 0
//   saturating   m = 1 + b * (1 - exp(-z / lam))   growth that levels off;
//                                                  lam = exp(q); linear growth
//                                                  is the lam >> z limit
//   decaying     m = 1 + b * exp(-z / lam)         run-in: extra wear early on
//   flag         m = exp(b * z)                    z in {0, 1}
//   binned       m = exp(b_k) for z in bin k >= 1  (bin 0: m = 1); bins are
//                                                  training quantiles: any shape
//   per-level    m = exp(b_l) for factor level l >= 1
// Measurement terms add to what the grinder reads, not to the wear:
//   offset-decay   y = d + A * exp(-z / tau)       tau = exp(q)
//   offset-linear  y = d + A * (z - c) / s
// A missing covariate value (NaN) leaves the prediction unchanged.
//
// Thread-safety: pure functions and plain values.
#ifndef ROLLWEAR_CORE_MODEL_MODEL_TERMS_H_
#define ROLLWEAR_CORE_MODEL_MODEL_TERMS_H_

#include <string>
#include <vector>

namespace rollwear {

enum class TermForm {
  kLogLinear, kPower, kSaturating, kDecaying, kFlag, kBinned, kPerLevel,
  kOffsetDecay, kOffsetLinear,
};
const char* TermFormName(TermForm f);  // "log_linear", "power", ...
bool ParseTermForm(const std::string& name, TermForm* out);

struct ModelTerm {
  std::string covariate;  // name in the covariate catalog (covariates.h)
  TermForm form = TermForm::kLogLinear;
  std::vector<double> params;  // see the table above
  double center = 0;           // c
  double scale = 1;            // s
  std::vector<double> edges;   // binned: upper edges of bins 0..B-2
  int num_levels = 0;          // per-level: number of factor levels
  // per-level: the factor's level labels, level l = levels[l] (the first
  // num_levels of the fitted data's levels). The daemon matches a record's
  // label to them (core/model/predictor.h); empty for a term stored before
  // labels were kept, which then counts as 1 coil by coil.
  std::vector<std::string> levels;

  bool IsMeasurementTerm() const {
    return form == TermForm::kOffsetDecay || form == TermForm::kOffsetLinear;
  }
  int NumParams() const;
};

// Wear-rate multiplier m(z) and, if grad != nullptr, dm/dparams
// (size NumParams()).
double TermMultiplier(const ModelTerm& t, double z, double* grad);
// Measurement offset (µm) and, if grad != nullptr, d/dparams.
double TermOffset(const ModelTerm& t, double z, double* grad);

// Index of the bin of z (binned form).
int TermBin(const ModelTerm& t, double z);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_MODEL_TERMS_H_
