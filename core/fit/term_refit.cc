#include "core/fit/term_refit.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "core/model/k_structure.h"
#include "core/fit/term_fit.h"

namespace rollwear {
namespace {

// Bounds of a refit around the adopted parameters: the amplitude ranges of
// the diagnosis candidates (diagnosis_candidates.cc), and length scales
// (log lam, log tau) within a factor 20 of the adopted value.
void Bounds(const ModelTerm& t, std::vector<double>* lo,
            std::vector<double>* hi) {
  const int n = t.NumParams();
  lo->assign(n, -3.0);
  hi->assign(n, 3.0);
  switch (t.form) {
    case TermForm::kLogLinear:
      (*lo)[0] = -2.0;
      (*hi)[0] = 2.0;
      break;
    case TermForm::kPower:
      (*lo)[0] = -4.0;
      (*hi)[0] = 4.0;
      break;
    case TermForm::kSaturating:
    case TermForm::kDecaying:
      (*lo)[0] = -0.9;
      (*hi)[0] = 10.0;
      (*lo)[1] = t.params[1] - std::log(20.0);
      (*hi)[1] = t.params[1] + std::log(20.0);
      break;
    case TermForm::kOffsetDecay:
      (*lo)[0] = -1000.0;
      (*hi)[0] = 1000.0;
      (*lo)[1] = t.params[1] - std::log(20.0);
      (*hi)[1] = t.params[1] + std::log(20.0);
      break;
    case TermForm::kOffsetLinear:
    case TermForm::kOffsetPerLevel:
    case TermForm::kOffsetBinned:
      lo->assign(n, -1000.0);
      hi->assign(n, 1000.0);
      break;
    default:
      break;  // flag, binned, per-level: +-3 in log space
  }
}

}  // namespace

StatusOr<WearModel> RefitWithTerms(const Dataset& data, WearLaw law,
                                   const std::vector<ModelTerm>& terms,
                                   const std::vector<int>& train_campaigns) {
  ROLLWEAR_ASSIGN_OR_RETURN(const TermData td, BuildTermData(data, law));
  std::vector<TermSpec> specs;
  for (const ModelTerm& t : terms) {
    TermSpec s;
    s.term = t;
    s.covariate = td.CovariateIndex(t.covariate);
    if (s.covariate < 0) {
      return Status::InvalidArgument("terms: covariate '" + t.covariate +
                                     "' is not in the data");
    }
    const bool on_measurement =
        td.catalog[s.covariate].level == CovariateLevel::kMeasurement;
    if (t.IsMeasurementTerm() != on_measurement) {
      return Status::InvalidArgument(
          "terms: '" + t.covariate + "' is a " +
          (on_measurement ? "measurement-side" : "wear-rate") + " covariate but form " +
          TermFormName(t.form) + " acts on the " +
          (t.IsMeasurementTerm() ? "measured value" : "wear rate"));
    }
    if (t.IsMeasurementTerm() && !t.scope.grade.empty()) {
      return Status::InvalidArgument("terms: '" + t.covariate +
                                     "' is a measurement term and cannot be scoped by "
                                     "grade (a reading is of a roll, not of a grade)");
    }
    if (static_cast<int>(t.params.size()) != t.NumParams()) {
      return Status::InvalidArgument(
          "terms: '" + t.covariate + "' (" + TermFormName(t.form) + ") has " +
          std::to_string(t.params.size()) + " parameters, expected " +
          std::to_string(t.NumParams()));
    }
    Bounds(t, &s.lower, &s.upper);
    if (t.form == TermForm::kCell) s.prior_sd = kCellPriorSd;
    for (int j = 0; j < t.NumParams(); ++j) {
      s.term.params[j] = std::clamp(t.params[j], s.lower[j], s.upper[j]);
    }
    specs.push_back(std::move(s));
  }
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
  model.terms.clear();
  for (const TermSpec& s : specs) model.terms.push_back(s.term);
  return model;
}

}  // namespace rollwear
