// The vocabulary of issue 15 as one model's terms, shared by the tests
// that check the daemon serves it as the batch path does
// (tests/core/served_terms_test.cc, tests/storage/store_history_test.cc).
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_TESTS_CORE_SERVED_TERMS_UTIL_H_
#define ROLLWEAR_TESTS_CORE_SERVED_TERMS_UTIL_H_

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/model/model_terms.h"

namespace rollwear::served_terms {

// Mean and sd of the passes' temperature: the log-linear term's c and s.
inline std::pair<double, double> TemperatureMoments(const Dataset& d) {
  double sum = 0, sum2 = 0;
  for (const Pass& p : d.passes) {
    sum += p.temperature_c;
    sum2 += p.temperature_c * p.temperature_c;
  }
  const double n = static_cast<double>(d.passes.size());
  return {sum / n, std::sqrt(std::max(1e-9, sum2 / n - (sum / n) * (sum / n)))};
}

// The four terms; `grinder` is the measurement text column's index.
inline std::vector<ModelTerm> VocabularyTerms(const Dataset& d, int grinder) {
  std::vector<ModelTerm> terms(4);
  const auto [c, s] = TemperatureMoments(d);
  terms[0].covariate = "temperature_c";  // log-linear, at F7 only
  terms[0].params = {0.3};
  terms[0].center = c;
  terms[0].scale = s;
  terms[0].scope.stand = 7;
  terms[1].covariate = kCellCovariateName;  // cell F6 x the first roll type
  terms[1].form = TermForm::kCell;
  terms[1].params = {0.25};
  terms[1].scope.stand = 6;
  terms[1].scope.roll_type = d.roll_types[0];
  ModelTerm& g = terms[2];  // per-level offset on the grinder column
  g.covariate = d.measurement_extra.factor_names[grinder];
  g.form = TermForm::kOffsetPerLevel;
  g.levels = d.measurement_extra.factor_levels[grinder];
  g.num_levels = static_cast<int>(g.levels.size());
  g.reference_level = 0;
  for (int l = 1; l < g.num_levels; ++l) g.params.push_back(-12.0 + 7.0 * l);
  ModelTerm& m = terms[3];  // calendar drift of the reading, top rolls only
  m.covariate = "measured_at";
  m.form = TermForm::kOffsetLinear;
  m.params = {4.0};
  m.center = static_cast<double>(d.measurements[0].measured_at) / 86400.0;
  m.scale = 30.0;
  m.scope.position = static_cast<int>(Position::kTop);
  return terms;
}

}  // namespace rollwear::served_terms

#endif  // ROLLWEAR_TESTS_CORE_SERVED_TERMS_UTIL_H_
