// Alternatives to a winner: the multiplicity policy and the encompassing
// test (diagnosis_alternatives.h).
#include "core/diagnosis/diagnosis_alternatives.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/base/distributions.h"

namespace rollwear::diag {

Multiplicity AnyOf(const DiagnosisThresholds& thresholds, double k) {
  return {thresholds.alternative_alpha, std::max(1.0, k)};
}

Multiplicity EachOf(const DiagnosisThresholds& thresholds) {
  return {thresholds.alternative_alpha, 1.0};
}

Multiplicity RoundFamily(const DiagnosisOptions& options, double num_tests) {
  return {options.alpha, std::max(1.0, num_tests)};
}

double NestedLr(double n, double rss_a, double rss_b) {
  return std::max(0.0, n * std::log(rss_a / rss_b));
}

Encompassing Encompassed(const DiagnosisState& st, const Fitted& base,
                         const Fitted& with, int df) {
  Encompassing e;
  e.df = df;
  e.with = with;
  if (!e.usable()) return e;
  e.lr = NestedLr(static_cast<double>(st.train.size()), base.rss, with.rss);
  e.p = ChiSquareSurvival(e.lr, df);
  return e;
}

Encompassing Encompass(const DiagnosisState& st, const std::vector<double>& sd,
                       const Fitted& base, const TermSpec& term) {
  return Encompassed(st, base, FitWith(st, sd, base, term),
                     term.term.NumParams());
}

StrongestAlternative Strongest(const DiagnosisState& st,
                               const std::vector<double>& sd,
                               const Fitted& base,
                               const std::vector<TermSpec>& alternatives) {
  StrongestAlternative best;
  for (size_t i = 0; i < alternatives.size(); ++i) {
    Encompassing e = Encompass(st, sd, base, alternatives[i]);
    if (e.usable() && e.p < best.test.p) {
      best.index = static_cast<int>(i);
      best.test = std::move(e);
    }
  }
  return best;
}

}  // namespace rollwear::diag
