#include "core/fit/term_refit.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "core/fit/calibration.h"
#include "core/fit/robust.h"
#include "core/fit/term_fit.h"
#include "core/model/aggregation.h"
#include "core/model/k_structure.h"
#include "core/model/term_family.h"

namespace rollwear {
namespace {

// A per-level term (per_level, offset_per_level) carries its parameters in
// the order of its own level labels; the data being fitted may meet its
// levels in another order or have new ones. Re-expresses `t` in the data's
// order (`c.levels`), matching by label: a label the term did not know
// starts at the baseline (multiplier 1, offset 0), and the reference level
// of an offset term keeps its label when the data have it. Terms stored
// without labels are left as they are (matched by index, as stored).
void AlignLevels(const CovariateSpec& c, ModelTerm* t) {
  if (t->form == TermForm::kRollEffect) {
    // No reference: every roll has its parameter, a new roll starts at 0
    // (its type's value).
    std::vector<double> params(c.levels.size(), 0.0);
    for (size_t l = 0; l < c.levels.size(); ++l) {
      for (size_t o = 0; o < t->levels.size() && o < t->params.size(); ++o) {
        if (t->levels[o] == c.levels[l]) params[l] = t->params[o];
      }
    }
    t->levels = c.levels;
    t->num_levels = static_cast<int>(c.levels.size());
    t->params = std::move(params);
    t->level_sd.clear();  // recomputed after the refit
    t->level_readings.clear();
    return;
  }
  const bool per_level = t->form == TermForm::kPerLevel;
  if ((!per_level && t->form != TermForm::kOffsetPerLevel) || t->levels.empty() ||
      c.levels.size() < 2) {
    return;
  }
  // The old value of each old label: multiplier exponent or offset, 0 at
  // the baseline / reference.
  const int old_ref = per_level ? 0 : t->reference_level;
  std::vector<double> old_value(t->levels.size(), 0.0);
  for (int l = 0, j = 0; l < static_cast<int>(t->levels.size()); ++l) {
    if (l == old_ref) continue;
    if (j < static_cast<int>(t->params.size())) old_value[l] = t->params[j];
    ++j;
  }
  auto value_of = [&](const std::string& label) {
    for (size_t l = 0; l < t->levels.size(); ++l) {
      if (t->levels[l] == label) return old_value[l];
    }
    return 0.0;
  };
  int new_ref = 0;
  if (!per_level) {
    const std::string ref_label = t->levels[old_ref];
    for (size_t l = 0; l < c.levels.size(); ++l) {
      if (c.levels[l] == ref_label) new_ref = static_cast<int>(l);
    }
  }
  const double base = value_of(c.levels[new_ref]);
  std::vector<double> params;
  for (int l = 0; l < static_cast<int>(c.levels.size()); ++l) {
    if (l != new_ref) params.push_back(value_of(c.levels[l]) - base);
  }
  t->levels = c.levels;
  t->num_levels = static_cast<int>(c.levels.size());
  t->reference_level = per_level ? 0 : new_ref;
  t->params = std::move(params);
}

// The grade prior of a refit (term_fit.h): the between-grade sd tau that
// option 1's calibration on the same training campaigns estimates
// (calibration.h, grade shrinkage); 0 (grades fitted freely) when the
// shrinkage does not apply or the calibration fails.
double GradePriorSd(const Dataset& data, WearLaw law,
                    const std::vector<int>& train_campaigns) {
  const DatasetIndex index(data);
  StatusOr<WearStatistics> stats = Aggregate(data, index, law);
  if (!stats.ok()) return 0;
  const std::vector<int> train = stats->MeasuredObservations(train_campaigns);
  if (train.empty()) return 0;
  CalibrationOptions co;
  co.law = law;
  co.compute_covariance = false;
  StatusOr<CalibrationResult> fit = Calibrate(*stats, train, co);
  if (!fit.ok() || !fit->summary.usable || !fit->grade_shrinkage.applied) {
    return 0;
  }
  return fit->grade_shrinkage.tau;
}

// The terms as fit specifications on `td`: each term's covariate found,
// its side (wear rate or reading) and parameter count checked, its levels
// aligned with the data's, its bounds and prior set.
StatusOr<std::vector<TermSpec>> SpecsOf(const TermData& td,
                                        const std::vector<ModelTerm>& terms) {
  std::vector<TermSpec> specs;
  for (const ModelTerm& t : terms) {
    TermSpec s;
    s.term = t;
    s.covariate = td.CovariateIndex(t.covariate);
    if (s.covariate < 0) {
      return Status::InvalidArgument("terms: covariate '" + t.covariate +
                                     "' is not in the data");
    }
    // A quantity the data format does not name is never served (the
    // predictor has no value for it): a term over it would fit one model
    // and serve another. roll_id is the roll-effect form's own.
    if (td.catalog[s.covariate].locate_only &&
        !(t.form == TermForm::kRollEffect &&
          td.catalog[s.covariate].source == CovariateSource::kRollId)) {
      return Status::InvalidArgument(
          "terms: '" + t.covariate +
          "' is derived by the diagnosis, not recorded: no term can use it");
    }
    const bool on_measurement =
        td.catalog[s.covariate].level == CovariateLevel::kMeasurement;
    if (t.IsMeasurementTerm() != on_measurement) {
      return Status::InvalidArgument(
          "terms: '" + t.covariate + "' is a " +
          (on_measurement ? "measurement-side" : "wear-rate") +
          " covariate but form " + TermFormName(t.form) + " acts on the " +
          (t.IsMeasurementTerm() ? "measured value"
           : t.IsAdditiveTerm()  ? "wear added per pass"
                                 : "wear rate"));
    }
    if (t.IsMeasurementTerm() && !t.scope.grade.empty()) {
      return Status::InvalidArgument("terms: '" + t.covariate +
                                     "' is a measurement term and cannot be scoped by "
                                     "grade (a reading is of a roll, not of a grade)");
    }
    if (!t.scope.gate.empty()) {
      const int g = td.CovariateIndex(t.scope.gate);
      if (t.IsMeasurementTerm() || t.form == TermForm::kRollEffect || g < 0 ||
          td.catalog[g].level != CovariateLevel::kPass ||
          td.catalog[g].kind != CovariateKind::kNumeric) {
        return Status::InvalidArgument(
            "terms: '" + t.covariate + "' is gated by '" + t.scope.gate +
            "', which must be a numeric pass-level covariate of the data, on "
            "a wear term other than a roll's own factor");
      }
    }
    if (static_cast<int>(t.params.size()) != t.NumParams()) {
      return Status::InvalidArgument(
          "terms: '" + t.covariate + "' (" + TermFormName(t.form) + ") has " +
          std::to_string(t.params.size()) + " parameters, expected " +
          std::to_string(t.NumParams()));
    }
    AlignLevels(td.catalog[s.covariate], &s.term);
    // The family's box around the adopted parameters (the amplitude ranges
    // the diagnosis proposes it with) and its prior (term_family.h).
    const TermFamily& family = FamilyOf(t.form);
    family.RefitBounds(s.term, &s.lower, &s.upper);
    s.prior_sd = family.PriorSd(t);
    for (int j = 0; j < s.term.NumParams(); ++j) {
      s.term.params[j] = std::clamp(s.term.params[j], s.lower[j], s.upper[j]);
    }
    specs.push_back(std::move(s));
  }
  return specs;
}

}  // namespace

StatusOr<WearModel> RefitWithTerms(const Dataset& data, WearLaw law,
                                   const std::vector<ModelTerm>& terms,
                                   const std::vector<int>& train_campaigns) {
  ROLLWEAR_ASSIGN_OR_RETURN(TermData td, BuildTermData(data, law));
  td.grade_prior_sd = GradePriorSd(data, law, train_campaigns);
  ROLLWEAR_ASSIGN_OR_RETURN(std::vector<TermSpec> specs, SpecsOf(td, terms));
  const std::set<int> train(train_campaigns.begin(), train_campaigns.end());
  std::vector<int> subset;
  for (int o = 0; o < static_cast<int>(td.obs.size()); ++o) {
    if (train.count(td.obs[o].campaign) > 0) subset.push_back(o);
  }
  if (subset.empty()) {
    return Status::FailedPrecondition(
        "no measured roll in the training campaigns");
  }

  // Pass 1: unit weights; passes 2 and 3: the robust noise model and Huber
  // weights of the previous pass (term_fit.h, TermNoiseSd): least squares,
  // then Huber IRLS with its scale iterated once.
  WearModel model;
  model.law = law;
  std::vector<double> sd(td.obs.size(), 1.0);
  std::vector<double> log_k;
  for (int pass = 0; pass < 3; ++pass) {
    ROLLWEAR_ASSIGN_OR_RETURN(TermFitResult fit,
                              FitTerms(td, subset, sd, log_k, specs));
    if (!fit.usable) {
      return Status::NumericalFailure("refit with terms did not converge");
    }
    log_k = std::move(fit.log_k);
    specs = std::move(fit.terms);
    sd = TermNoiseSd(td, subset, log_k, specs, &model);
  }
  ROLLWEAR_ASSIGN_OR_RETURN(
      model.structure,
      KStructure::ForOption(1, td.positions, td.roll_types, td.grades));
  model.k.clear();
  for (double lk : log_k) model.k.push_back(std::exp(lk));
  SetRollEffectSpread(td, subset, sd, log_k, &specs);
  // The served interval covers the training readings' tails (robust.h).
  const std::vector<double> pred = PredictTerms(td, subset, log_k, specs);
  std::vector<double> u;
  for (size_t i = 0; i < subset.size(); ++i) {
    const double sd_i =
        std::hypot(model.noise_sd_um, model.noise_rel * pred[i]);
    u.push_back((td.obs[subset[i]].measured_um - pred[i]) / sd_i);
  }
  const double c = TailCoverageScale(u);
  model.noise_sd_um *= c;
  model.noise_rel *= c;
  model.terms.clear();
  for (const TermSpec& s : specs) model.terms.push_back(s.term);
  return model;
}

void SetRollEffectSpread(const TermData& td, const std::vector<int>& subset,
                         const std::vector<double>& sd,
                         const std::vector<double>& log_k,
                         std::vector<TermSpec>* terms) {
  const std::vector<double> pred = PredictTerms(td, subset, log_k, *terms, true);
  for (TermSpec& s : *terms) {
    ModelTerm& t = s.term;
    if (t.form != TermForm::kRollEffect) continue;
    std::vector<double> info(t.num_levels, 0.0);
    t.level_readings.assign(t.num_levels, 0);
    for (size_t i = 0; i < subset.size(); ++i) {
      const TermObservation& ob = td.obs[subset[i]];
      if (ob.pass_end <= ob.pass_begin) continue;
      const double z = td.z[s.covariate][ob.pass_begin];
      if (!(z >= 0 && z < t.num_levels)) continue;
      const int l = static_cast<int>(z);
      info[l] += (pred[i] / sd[subset[i]]) * (pred[i] / sd[subset[i]]);
      ++t.level_readings[l];
    }
    const double prior = s.prior_sd > 0 ? 1 / (s.prior_sd * s.prior_sd) : 0;
    t.level_sd.assign(t.num_levels, 0.0);
    for (int l = 0; l < t.num_levels; ++l) {
      t.level_sd[l] = info[l] + prior > 0 ? 1 / std::sqrt(info[l] + prior) : t.scale;
    }
  }
}

}  // namespace rollwear
