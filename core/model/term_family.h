// Term families: the plug-in point of model terms (model_terms.h), as Ceres
// has its loss functions and manifolds. A family is one form of term (the
// log-linear multiplier, the cell, the offset by level, ...): its stored
// name, its parameter count, its multiplier or offset with derivatives, the
// bounds and prior its refit uses, and the rules its stored form obeys.
// Each family lives in its own file (term_family_<name>.cc) and is listed
// once in the registry (term_family.cc); nothing outside those files
// switches on the form to compute a term. Adding a family: a TermForm
// value, one file, one line in the registry.
//
// What the diagnosis proposes and how it words a finding are still its own
// (core/diagnosis/diagnosis_candidates.cc, diagnosis_naming.cc); see
// docs/diagnosis.md, "Term families".
//
// Thread-safety: families are stateless singletons built on first use
// (function-local statics); every method is const and may be called from
// any thread.
#ifndef ROLLWEAR_CORE_MODEL_TERM_FAMILY_H_
#define ROLLWEAR_CORE_MODEL_TERM_FAMILY_H_

#include <optional>
#include <string>
#include <vector>

#include "core/model/model_terms.h"

namespace rollwear {

// A stored term that breaks its family's rules: the field and why.
struct TermFieldError {
  std::string field;    // "center", "form", "levels", ...
  std::string message;  // "must be > 0 for the power form (z / center)^b"
};

class TermFamily {
 public:
  virtual ~TermFamily() = default;

  virtual TermForm form() const = 0;
  // The stored name (the model JSON's "form", the finding's `form`).
  virtual const char* name() const = 0;
  // Whether the term offsets what the grinder reads (TermOffset) rather
  // than multiplying the wear rate (TermMultiplier).
  virtual bool measurement() const { return false; }
  virtual int NumParams(const ModelTerm& /*t*/) const { return 1; }
  // The multiplier m(z) (a wear-rate family) or the offset in µm (a
  // measurement family) at a finite z, and into grad (NumParams() values,
  // zeroed by the caller) its derivatives by the parameters.
  virtual double Evaluate(const ModelTerm& t, double z, double* grad) const = 0;
  // Whether the multiplier is m = exp(b u(z)), one parameter b and u fixed
  // by the term's center and scale (log-linear, power, flag): the term fits
  // then compute u of every pass once per fit (core/fit/
  // term_model_internal.h) and Evaluate is exp(b u) by the same u.
  virtual bool exponential() const { return false; }
  // u(z) of an exponential family at a finite z.
  virtual double Exponent(const ModelTerm& /*t*/, double z) const { return z; }
  // The box of a refit around the adopted parameters `t.params`
  // (core/fit/term_refit.cc): by default +-3 on each log-multiplier, the
  // amplitude range the diagnosis proposes the family with.
  virtual void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                           std::vector<double>* hi) const;
  // The sd of the normal prior on each parameter in a fit (term_fit.h's
  // TermSpec::prior_sd), 0 for none.
  virtual double PriorSd(const ModelTerm& /*t*/) const { return 0; }
  // The family's own rules on a stored term (storage/model_codec.cc checks
  // the shared ones), nullopt when it obeys them.
  virtual std::optional<TermFieldError> CheckStored(const ModelTerm& t) const;
};

// The family of form `f`.
const TermFamily& FamilyOf(TermForm f);
// The family stored under `name`, or nullptr.
const TermFamily* FamilyNamed(const std::string& name);
// Every registered family, in TermForm order.
const std::vector<const TermFamily*>& AllTermFamilies();

// Refit boxes shared by several families: an amplitude in [amp_lo, amp_hi]
// and a length scale stored as its log (lam = exp(q), tau = exp(q)) within a
// factor 20 of the adopted value `adopted_log` (saturating, decaying,
// offset-decay); and every parameter in [-bound, bound] (the offsets, in µm).
void AmplitudeAndLogScaleBounds(double amp_lo, double amp_hi,
                                double adopted_log, std::vector<double>* lo,
                                std::vector<double>* hi);
void SymmetricBounds(int n, double bound, std::vector<double>* lo,
                     std::vector<double>* hi);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_TERM_FAMILY_H_
