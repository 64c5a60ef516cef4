// Shared by the core and storage tests of terms on a mill's extra columns:
// extra columns added to a simulated dataset (a numeric pass column with
// empty cells, a campaign factor whose empty text is a level and one of
// whose levels the terms never saw, a roll factor, a numeric measurement
// column), terms adopted on them, and the batch prediction of the
// diagnosis engine (PredictTerms over BuildTermData, core/fit/term_fit.h),
// which reads the extra columns by row index from the Dataset.
//
// Thread-safety: plain functions over values.
#ifndef ROLLWEAR_TESTS_CORE_EXTRA_TERMS_UTIL_H_
#define ROLLWEAR_TESTS_CORE_EXTRA_TERMS_UTIL_H_

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset.h"
#include "core/fit/term_fit.h"
#include "core/model/k_structure.h"
#include "core/model/wear_model.h"

namespace rollwear::extra_terms_test {

inline constexpr const char* kCoolant = "coolant_bar";   // pass, numeric
inline constexpr const char* kCrew = "crew";             // campaign, factor
inline constexpr const char* kSupplier = "supplier";     // roll, factor
inline constexpr const char* kProbe = "probe_temp_c";    // measurement

// Coolant pressure of pass row `row` (NaN every 7th row: an empty cell).
inline double CoolantOfRow(size_t row) {
  if (row % 7 == 3) return std::numeric_limits<double>::quiet_NaN();
  return 1.9 + 0.013 * static_cast<double>(row % 41);
}
// Crew of campaign `c`: levels in first-seen order A, B, "" (empty), C.
inline std::string CrewOf(size_t c) {
  static const char* kCrews[] = {"A", "B", "", "C"};
  return kCrews[c % 4];
}
// Supplier of mount `m`: levels in first-seen order Y, X.
inline std::string SupplierOf(size_t mount) { return mount % 3 == 0 ? "Y" : "X"; }

inline void AddFactor(ExtraColumns* e, const std::string& name,
                      const std::vector<std::string>& values) {
  std::vector<int> codes;
  std::vector<std::string> levels;
  for (const std::string& v : values) {
    size_t l = 0;
    while (l < levels.size() && levels[l] != v) ++l;
    if (l == levels.size()) levels.push_back(v);
    codes.push_back(static_cast<int>(l));
  }
  e->factor_names.push_back(name);
  e->factor.push_back(std::move(codes));
  e->factor_levels.push_back(std::move(levels));
}

inline void AddExtraColumns(Dataset* d) {
  std::vector<double> coolant(d->passes.size());
  for (size_t i = 0; i < coolant.size(); ++i) coolant[i] = CoolantOfRow(i);
  d->pass_extra.numeric_names.push_back(kCoolant);
  d->pass_extra.numeric.push_back(std::move(coolant));
  std::vector<std::string> crews, suppliers;
  for (size_t c = 0; c < d->campaigns.size(); ++c) crews.push_back(CrewOf(c));
  for (size_t m = 0; m < d->mounts.size(); ++m) suppliers.push_back(SupplierOf(m));
  AddFactor(&d->campaign_extra, kCrew, crews);
  AddFactor(&d->mount_extra, kSupplier, suppliers);
  std::vector<double> probe(d->measurements.size());
  for (size_t i = 0; i < probe.size(); ++i) probe[i] = 20 + (i % 9) * 2.5;
  d->measurement_extra.numeric_names.push_back(kProbe);
  d->measurement_extra.numeric.push_back(std::move(probe));
}

// Terms on the four columns: log-linear on the pass column, per-level on
// the campaign factor (levels A, B, "": C is a level they never saw) and
// on the roll factor, offset-linear on the measurement column.
inline std::vector<ModelTerm> ExtraTerms() {
  ModelTerm coolant;
  coolant.covariate = kCoolant;
  coolant.form = TermForm::kLogLinear;
  coolant.params = {0.3};
  coolant.center = 2.15;
  coolant.scale = 0.15;
  ModelTerm crew;
  crew.covariate = kCrew;
  crew.form = TermForm::kPerLevel;
  crew.num_levels = 3;
  crew.levels = {"A", "B", ""};
  crew.params = {0.25, -0.2};
  ModelTerm supplier;
  supplier.covariate = kSupplier;
  supplier.form = TermForm::kPerLevel;
  supplier.num_levels = 2;
  supplier.levels = {"Y", "X"};  // the data's order, as a fit keeps them
  supplier.params = {0.15};
  ModelTerm probe;
  probe.covariate = kProbe;
  probe.form = TermForm::kOffsetLinear;
  probe.center = 30;
  probe.scale = 5;
  probe.params = {4.0};
  return {coolant, crew, supplier, probe};
}

// Wang, option 1 over td's levels, coefficients varying by index, `terms`.
inline WearModel ModelWithTerms(const TermData& td, std::vector<ModelTerm> terms) {
  WearModel m;
  m.law = WearLaw::kWang;
  m.structure = *KStructure::ForOption(1, td.positions, td.roll_types, td.grades);
  for (int i = 0; i < m.structure.num_coefficients(); ++i) {
    m.k.push_back(0.3 * (1 + 0.04 * (i % 5)));
  }
  m.terms = std::move(terms);
  m.noise_sd_um = 5;
  m.noise_rel = 0.05;
  return m;
}

// The diagnosis engine's batch prediction of every observation of td
// (wear only, or with the measurement terms).
inline std::vector<double> BatchPrediction(const TermData& td, const WearModel& m,
                                           bool wear_only) {
  std::vector<double> log_k;
  for (double k : m.k) log_k.push_back(std::log(k));
  std::vector<TermSpec> specs;
  for (const ModelTerm& t : m.terms) {
    TermSpec s;
    s.term = t;
    s.covariate = td.CovariateIndex(t.covariate);
    EXPECT_GE(s.covariate, 0) << t.covariate;
    specs.push_back(s);
  }
  std::vector<int> all(td.obs.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return PredictTerms(td, all, log_k, specs, wear_only);
}

// A speed multiplier beside another term: exp(0.2 (v - 10) / 2).
inline ModelTerm SpeedTerm() {
  ModelTerm speed;
  speed.covariate = "speed_mps";
  speed.form = TermForm::kLogLinear;
  speed.params = {0.2};
  speed.center = 10;
  speed.scale = 2;
  return speed;
}

}  // namespace rollwear::extra_terms_test

#endif  // ROLLWEAR_TESTS_CORE_EXTRA_TERMS_UTIL_H_
