// Internal pieces of the diagnosis engine (diagnosis.h): the candidate
// library, the naming of mechanisms, and the residual breakdowns. Include
// only from diagnosis*.cc.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_INTERNAL_H_
#define ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_INTERNAL_H_

#include <set>
#include <vector>

#include "core/diagnosis/diagnosis.h"
#include "core/fit/term_fit.h"

namespace rollwear::diag {

struct Candidate {
  TermSpec spec;
  // Alternative starting parameter vectors (non-linear parameters such as
  // a length scale are tried on a small grid; the best fit is kept).
  std::vector<std::vector<double>> starts;
};

// Every candidate term over covariates not in `used`.
std::vector<Candidate> MakeCandidates(const TermData& td, const std::vector<int>& train,
                                      const std::set<int>& used,
                                      const DiagnosisOptions& options);

// Appends the scoped variants of the simple candidates already in `out`
// and the cell candidates (diagnosis_scoped.cc).
void AddScopedCandidates(const TermData& td, const std::vector<int>& train,
                         const std::set<int>& used, std::vector<Candidate>* out);

// Fills mechanism, shape and explanation of a finding from its fitted term
// and the covariate's training range (reads f->parameter_std_errors when
// set, to tell a noisy binned step from a peak).
void NameFinding(const TermData& td, const std::vector<int>& train, const TermSpec& spec,
                 Finding* finding);

// Residual breakdowns of `pred` (aligned with `obs`), strongest first;
// with `clip_sd` (aligned with `obs`) each residual is clipped to
// +-kHuberK * clip_sd first (robust.h).
std::vector<Breakdown> Locate(const TermData& td, const Dataset& data,
                              const std::vector<int>& obs,
                              const std::vector<double>& pred,
                              const std::vector<double>* clip_sd = nullptr);

// Load-weighted quantile q in [0, 1] of covariate k over the passes of
// `obs` (or of the aggregated values for non-pass covariates).
double CovariateQuantile(const TermData& td, const std::vector<int>& obs, int k, double q);

}  // namespace rollwear::diag

#endif  // ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_INTERNAL_H_
