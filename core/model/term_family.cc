#include "core/model/term_family.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>

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

int ModelTerm::NumParams() const { return FamilyOf(form).NumParams(*this); }

double TermMultiplier(const ModelTerm& t, double z, double* grad) {
  const TermFamily& family = FamilyOf(t.form);
  if (grad != nullptr) std::fill(grad, grad + family.NumParams(t), 0.0);
  if (std::isnan(z) || family.measurement()) return 1.0;
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

std::optional<TermFieldError> TermFamily::CheckStored(
    const ModelTerm& t) const {
  // The predictor reads a roll_effect term by the mounted roll's id
  // whatever its covariate, so roll_id takes no other form.
  if (t.covariate == kRollIdName) {
    return TermFieldError{"form",
                          "roll_effect is the form of covariate "
                          "roll_id, and roll_id takes no other"};
  }
  if (!t.level_sd.empty() || !t.level_readings.empty()) {
    return TermFieldError{"level_sd", "is only for the roll_effect form"};
  }
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

// The registry: one line per family, in TermForm order (checked below).
std::vector<const TermFamily*> Registry() {
  std::vector<const TermFamily*> f = {
      &LogLinearFamily(),    &PowerFamily(),          &SaturatingFamily(),
      &DecayingFamily(),     &FlagFamily(),           &BinnedFamily(),
      &PerLevelFamily(),     &CellFamily(),           &OffsetDecayFamily(),
      &OffsetLinearFamily(), &OffsetPerLevelFamily(), &OffsetBinnedFamily(),
      &RollEffectFamily(),
  };
  for (size_t i = 0; i < f.size(); ++i) {
    // A family listed out of TermForm order would make FamilyOf answer for
    // the wrong form: fail at once rather than compute a wrong term.
    if (static_cast<size_t>(f[i]->form()) != i) std::abort();
  }
  return f;
}

}  // namespace

const std::vector<const TermFamily*>& AllTermFamilies() {
  static const std::vector<const TermFamily*> families = Registry();
  return families;
}

const TermFamily& FamilyOf(TermForm f) {
  return *AllTermFamilies()[static_cast<size_t>(f)];
}

const TermFamily* FamilyNamed(const std::string& name) {
  for (const TermFamily* f : AllTermFamilies()) {
    if (name == f->name()) return f;
  }
  return nullptr;
}

}  // namespace rollwear
