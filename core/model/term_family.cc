#include "core/model/term_family.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>
#include <utility>

#include "core/model/covariates.h"
#include "core/model/term_family_list.h"

namespace rollwear {

// The functions of model_terms.h that ask a term's family, defined here so
// that model_terms does not include the families that include it.

const char* TermFormName(TermForm f) { return FamilyOf(f).name(); }

bool ParseTermForm(const std::string& name, TermForm* out) {
  const TermFamily* f = FamilyNamed(name);
  if (f == nullptr) return false;
  *out = f->form();
  return true;
}

bool ModelTerm::IsMeasurementTerm() const {
  return FamilyOf(form).measurement();
}

bool ModelTerm::IsAdditiveTerm() const { return FamilyOf(form).additive(); }

int ModelTerm::NumParams() const { return FamilyOf(form).NumParams(*this); }

double TermMultiplier(const ModelTerm& t, double z, double* grad) {
  const TermFamily& family = FamilyOf(t.form);
  if (grad != nullptr) std::fill(grad, grad + family.NumParams(t), 0.0);
  if (std::isnan(z) || family.measurement() || family.additive()) return 1.0;
  return family.Evaluate(t, z, grad);
}

double TermAddend(const ModelTerm& t, double z, double* grad) {
  const TermFamily& family = FamilyOf(t.form);
  if (grad != nullptr) std::fill(grad, grad + family.NumParams(t), 0.0);
  if (std::isnan(z) || !family.additive()) return 0.0;
  return family.Evaluate(t, z, grad);
}

double TermOffset(const ModelTerm& t, double z, double* grad) {
  const TermFamily& family = FamilyOf(t.form);
  if (grad != nullptr) std::fill(grad, grad + family.NumParams(t), 0.0);
  if (std::isnan(z) || !family.measurement()) return 0.0;
  return family.Evaluate(t, z, grad);
}

void TermFamily::RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                             std::vector<double>* hi) const {
  SymmetricBounds(NumParams(t), 3.0, lo, hi);
}

std::optional<TermFieldError> TermFamily::NoRollEffectFields(
    const ModelTerm& t) {
  if (t.covariate == kRollIdName) {
    return TermFieldError{"form",
                          "roll_effect is the form of covariate "
                          "roll_id, and roll_id takes no other"};
  }
  if (!t.level_sd.empty() || !t.level_readings.empty()) {
    return TermFieldError{"level_sd", "is only for the roll_effect form"};
  }
  return std::nullopt;
}

TermParamView TermFamily::Param(int j, double x) const {
  return {"parameter " + std::to_string(j), x};
}

std::optional<TermFieldError> TermFamily::CheckStored(
    const ModelTerm& t) const {
  if (std::optional<TermFieldError> e = NoRollEffectFields(t)) return e;
  if (t.reference_level != 0) {
    return TermFieldError{"reference_level",
                          "is only for the offset_per_level form"};
  }
  return std::nullopt;
}

std::string WordFormat(const char* fmt, double a, double b, double c,
                       double d) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c, d);
  return buf;
}

double StdErrorOf(const TermWordingInput& in, size_t j) {
  if (in.std_errors == nullptr) return std::nan("");
  const auto se = in.std_errors->find("param" + std::to_string(j));
  return se == in.std_errors->end() ? std::nan("") : se->second;
}

TermProposal Proposal(const TermFamily& family, const CovariateSummary& c,
                      std::vector<double> start, std::vector<double> lo,
                      std::vector<double> hi) {
  TermProposal p;
  p.term.covariate = c.spec->name;
  p.term.form = family.form();
  p.term.params = std::move(start);
  p.lower = std::move(lo);
  p.upper = std::move(hi);
  return p;
}

bool NumericOn(const CovariateSummary& c, bool measurement) {
  return c.spec->kind == CovariateKind::kNumeric &&
         (c.spec->level == CovariateLevel::kMeasurement) == measurement;
}

bool GrowsWithinCampaign(const CovariateSummary& c) {
  return NumericOn(c, false) && c.spec->accumulates && c.p95 > 0 && c.p05 >= 0;
}

TermProposal PerLevelProposal(const TermFamily& family,
                              const CovariateSummary& c, double bound) {
  const size_t n = static_cast<size_t>(c.levels - 1);
  TermProposal p =
      Proposal(family, c, std::vector<double>(n, 0.0),
               std::vector<double>(n, -bound), std::vector<double>(n, bound));
  p.term.num_levels = c.levels;
  const std::vector<std::string>& labels = c.spec->levels;
  p.term.levels.assign(
      labels.begin(),
      labels.begin() + std::min<size_t>(c.levels, labels.size()));
  return p;
}

void WordAmplitudeAndLengthScale(const ModelTerm& t, const TermWordingInput& in,
                                 TermWording* out) {
  const double lam = std::exp(t.params[1]);
  std::tie(out->shape, out->up) = in.profile_shape();
  out->parameters = {{"beta", t.params[0]}, {"lambda", lam}};
  out->fitted = in.range_text + ", length scale " + in.readable(lam);
}

void AmplitudeAndLogScaleBounds(double amp_lo, double amp_hi,
                                double adopted_log, std::vector<double>* lo,
                                std::vector<double>* hi) {
  *lo = {amp_lo, adopted_log - std::log(20.0)};
  *hi = {amp_hi, adopted_log + std::log(20.0)};
}

void SymmetricBounds(int n, double bound, std::vector<double>* lo,
                     std::vector<double>* hi) {
  lo->assign(n, -bound);
  hi->assign(n, bound);
}

namespace {

struct Registry {
  std::vector<const TermFamily*> all;      // in the order they propose
  std::vector<const TermFamily*> by_form;  // indexed by TermForm
};

// The registry: one line per family, in the order the diagnosis asks them
// for candidates (the order its ties between equally good candidates
// follow): the readings' families, then the wear rate's.
Registry Build() {
  Registry r;
  r.all = {
      &OffsetPerLevelFamily(), &PerLevelFamily(),     &FlagFamily(),
      &OffsetLinearFamily(),   &OffsetBinnedFamily(), &OffsetDecayFamily(),
      &LogLinearFamily(),      &PowerFamily(),        &BinnedFamily(),
      &SaturatingFamily(),     &DecayingFamily(),     &CellFamily(),
      &RollEffectFamily(),     &PerCoilFamily(),      &HingeFamily(),
  };
  r.by_form.assign(r.all.size(), nullptr);
  for (const TermFamily* f : r.all) {
    const size_t i = static_cast<size_t>(f->form());
    // A form without its family, or with two, would make FamilyOf answer
    // wrong: fail at once rather than compute a wrong term.
    if (i >= r.by_form.size() || r.by_form[i] != nullptr) std::abort();
    r.by_form[i] = f;
  }
  return r;
}

const Registry& TheRegistry() {
  static const Registry registry = Build();
  return registry;
}

}  // namespace

const std::vector<const TermFamily*>& AllTermFamilies() {
  return TheRegistry().all;
}

const TermFamily& FamilyOf(TermForm f) {
  return *TheRegistry().by_form[static_cast<size_t>(f)];
}

const TermFamily* FamilyNamed(const std::string& name) {
  for (const TermFamily* f : AllTermFamilies()) {
    if (name == f->name()) return f;
  }
  return nullptr;
}

}  // namespace rollwear
