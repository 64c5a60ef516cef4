// Term families: the plug-in point of model terms (model_terms.h), as Ceres
// has its loss functions and manifolds. A family is one form of term (the
// log-linear multiplier, the cell, the offset by level, ...): its stored
// name, its parameter count, its multiplier, added wear or reading offset
// with derivatives, the bounds and prior its refit uses, and the rules its
// stored form obeys.
// Each family lives in its own file (term_family_<name>.cc) and is listed
// once in the registry (term_family.cc); nothing outside those files
// switches on the form to compute a term. Adding a family: a TermForm
// value, one file, one line in the registry.
//
// A family also proposes its candidate terms over a covariate to the
// diagnosis (Propose: starting values, box and further starts) and words a
// finding of its fitted term (Word: the shape, the parameters, the
// "Fitted:" sentence, and the mechanism where its physics is its form's);
// the diagnosis adds the calendar steps, the scopes, the covariate's
// mechanism and the scope's words (core/diagnosis/
// diagnosis_candidates.cc, diagnosis_naming.cc); see docs/diagnosis.md,
// "Term families".
//
// Thread-safety: families are stateless singletons built on first use
// (function-local statics); every method is const and may be called from
// any thread.
#ifndef ROLLWEAR_CORE_MODEL_TERM_FAMILY_H_
#define ROLLWEAR_CORE_MODEL_TERM_FAMILY_H_

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/model/covariates.h"
#include "core/model/model_terms.h"

namespace rollwear {

// A stored term that breaks its family's rules: the field and why.
struct TermFieldError {
  std::string field;    // "center", "form", "levels", ...
  std::string message;  // "must be > 0 for the power form (z / center)^b"
};

class TermFamily;

// What the diagnosis knows of a covariate when it asks the families for
// candidate terms over it: the covariate, and its training values (weighted
// by load for a pass-level covariate) summarised. The diagnosis asks only
// for a covariate that can carry a term: a factor of 2 or more levels, a
// flag on for 2..98 % of the weight, a numeric covariate that varies.
struct CovariateSummary {
  const CovariateSpec* spec = nullptr;
  int levels = 0;                    // a factor: levels seen (largest + 1)
  std::vector<double> level_weight;  // a factor: its weight per level
  double p01 = 0, p05 = 0, p50 = 0, p95 = 0;  // weighted quantiles
  double mean = 0, sd = 0, max = 0;
  std::vector<double> edges;  // distinct inner edges of equal-weight bins
};

// A candidate term a family proposes: its starting term, the box of its
// fit and further starting parameter vectors to try.
struct TermProposal {
  ModelTerm term;
  std::vector<double> lower, upper;
  std::vector<std::vector<double>> starts;
};

// What the diagnosis gives a family to word a finding of its fitted term.
struct TermWordingInput {
  // The multiplier's shape over the covariate's 5th..95th percentiles
  // ("increasing", "saturating_growth", "peaked", ...) and whether it
  // rises, computed by the diagnosis (diagnosis_naming.cc) on demand.
  std::function<std::pair<std::string, bool>()> profile_shape;
  // "wear-rate multiplier 0.912 at the 5th percentile (800 °C) and 1.104
  // at the 95th (1,010 °C)".
  std::string range_text;
  // A covariate value with its unit and a readable magnitude ("96.7 km").
  std::function<std::string(double)> readable;
  // The fit's standard errors by parameter ("param0", ...); may be empty.
  const std::map<std::string, double>* std_errors = nullptr;
};

// A family's words for a finding (the finding's fields of the same names).
struct TermWording {
  std::string shape;
  std::map<std::string, double> parameters;
  // The affected levels, for the families that name levels.
  std::optional<std::vector<std::string>> levels;
  std::string fitted;  // the sentence after "Fitted: "
  // The multiplier (or offset) rises with the covariate: the naming picks
  // the covariate's "up" or "down" mechanism by it (diagnosis_naming.cc).
  bool up = true;
  // A family whose physics is its form's, not its covariate's (wear per
  // coil): the mechanism's name and sentence; empty: the diagnosis names
  // the mechanism from the covariate (diagnosis_naming.cc).
  std::string mechanism, mechanism_text;
};

// A proposal of `family` over covariate `c` with starting parameters
// `start` in the box [lo, hi].
TermProposal Proposal(const TermFamily& family, const CovariateSummary& c,
                      std::vector<double> start, std::vector<double> lo,
                      std::vector<double> hi);
// Whether `c` is numeric, on the reading's side (a measurement covariate)
// or not.
bool NumericOn(const CovariateSummary& c, bool measurement);
// Whether `c` is a wear-rate quantity that grows within a campaign from 0
// on (rolled length, coils, hours: CovariateSpec::accumulates), the
// covariates of the saturating and decaying families.
bool GrowsWithinCampaign(const CovariateSummary& c);
// A proposal with one parameter per factor level but the reference, in the
// box [-bound, bound], labelled with the covariate's levels.
TermProposal PerLevelProposal(const TermFamily& family,
                              const CovariateSummary& c, double bound);

// A parameter as the family's formula names it (TermFamily::Param).
struct TermParamView {
  std::string name;
  double value = 0;
};

// printf of up to four doubles into a string (the wording's numbers).
std::string WordFormat(const char* fmt, double a, double b = 0, double c = 0,
                       double d = 0);
// The standard error of parameter j from `in`, NaN when it has none.
double StdErrorOf(const TermWordingInput& in, size_t j);

class TermFamily {
 public:
  virtual ~TermFamily() = default;

  virtual TermForm form() const = 0;
  // The stored name (the model JSON's "form", the finding's `form`).
  virtual const char* name() const = 0;
  // Whether the term offsets what the grinder reads (TermOffset) rather
  // than multiplying the wear rate (TermMultiplier).
  virtual bool measurement() const { return false; }
  // Whether the term adds Evaluate µm of wear on every pass it covers
  // (TermAddend: wear per coil) rather than multiplying the wear rate.
  virtual bool additive() const { return false; }
  // Whether the family's physics is its form's, not its covariate's (wear
  // per coil, over the coil count): its findings name the family's
  // mechanism (TermWording::mechanism), and the quantities that carry its
  // covariate's mechanism (the rolled length and hours beside the coils:
  // core/diagnosis/diagnosis_carriers.cc) do not carry it.
  virtual bool names_mechanism() const { return false; }
  // Whether the multiplier also scales the additive families' wear (the
  // roll-effect family: a roll's own wear resistance acts on all its wear,
  // so that its factor is the ratio of its wear to its type's whatever the
  // terms: core/model/roll_factor_update.h).
  virtual bool scales_added_wear() const { return false; }
  // Whether the diagnosis also offers the family's unscoped candidates at
  // each single scope (a stand, a roll position, a roll type, a grade:
  // core/diagnosis/diagnosis_scoped.cc): log-linear, flag, per-coil.
  virtual bool offered_scoped() const { return false; }
  // Whether the diagnosis also offers the family's unscoped candidates
  // behind each gate (TermScope::gate: the passes above or below a
  // quantile of another numeric pass-level covariate, core/diagnosis/
  // diagnosis_gates.cc): the flag, whose effect may act only above some
  // speed.
  virtual bool offered_gated() const { return false; }
  // Whether parameter j's lower (or upper) bound in the diagnosis's box is
  // a limit of the family's shape or of physics, where the fitted term is
  // still what the family describes (the saturating form's: linear growth,
  // a step; wear per coil's 0), rather than an arbitrary bracket, where a
  // fit that stops there wants to go on and the form stands in for
  // something it does not describe (core/diagnosis/diagnosis_rivals.cc,
  // AtBoxBound). Brackets by default.
  virtual bool BoundIsALimit(int /*j*/, bool /*upper*/) const { return false; }
  // Whether the term's `scale` may be negative (its sign carries meaning:
  // the hinge's side of the knee); otherwise a stored scale must be > 0
  // (storage/model_codec.cc).
  virtual bool SignedScale() const { return false; }
  // Parameter j at the fitted value x as a reader of the family's formula
  // knows it: its name there and x on that scale (a parameter fitted on a
  // log scale is shown exponentiated: "lam = 3200" for q = log lam).
  // Default: "parameter j" and x itself.
  virtual TermParamView Param(int j, double x) const;
  virtual int NumParams(const ModelTerm& /*t*/) const { return 1; }
  // The multiplier m(z) (a wear-rate family), the wear added per pass in
  // µm (an additive family) or the offset in µm (a measurement family) at
  // a finite z, and into grad (NumParams() values,
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
  // Appends the family's candidate terms over covariate `c` (none by
  // default: the cell and roll-effect families are proposed by the
  // diagnosis's own stages).
  virtual void Propose(const CovariateSummary& /*c*/,
                       std::vector<TermProposal>* /*out*/) const {}
  // The words of a diagnosis finding of the fitted term `t`; the default
  // leaves `out` as it is (the roll-effect family: the diagnosis's per-roll
  // stage words it, core/diagnosis/diagnosis_roll_family.cc).
  virtual void Word(const ModelTerm& /*t*/, const TermWordingInput& /*in*/,
                    TermWording* /*out*/) const {}
  // The family's own rules on a stored term (storage/model_codec.cc checks
  // the shared ones), nullopt when it obeys them.
  // By default: NoRollEffectFields, and no reference level.
  virtual std::optional<TermFieldError> CheckStored(const ModelTerm& t) const;

 protected:
  // The rules of every family but roll_effect: roll_id is roll_effect's
  // covariate alone (the predictor reads such a term by the mounted roll's
  // id whatever its covariate), and the per-roll spread is its alone.
  static std::optional<TermFieldError> NoRollEffectFields(const ModelTerm& t);
};

// The family of form `f`.
const TermFamily& FamilyOf(TermForm f);
// The family stored under `name`, or nullptr.
const TermFamily* FamilyNamed(const std::string& name);
// Every registered family, in the order the diagnosis asks them for
// candidates.
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
// The words of a multiplier 1 + b g(z / lam) with lam = exp(q) (the
// saturating and decaying families): the profile's shape, beta and lambda,
// and the range sentence with the length scale.
void WordAmplitudeAndLengthScale(const ModelTerm& t, const TermWordingInput& in,
                                 TermWording* out);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_TERM_FAMILY_H_
