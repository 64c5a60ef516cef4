// The per-coil family: wear that each coil adds whatever its length and
// load, a (µm) on every pass of the rolls it covers:
//   w = sum over passes i of [ k_g(i) load_i prod_t m_t(z_t,i) + a ],
// so a campaign of N coils adds a N to its roll's wear. The bite's impact
// at threading and the strip's head and tail (a thermal and mechanical
// shock per coil, not per metre) wear the roll this way; the Archard-type
// laws (Wang 2014; Nikitenko 2015; Cao 2019: wear proportional to the
// rolled length under load) leave it out. Proposed over the coil count
// (campaign_coils_before), the one covariate that counts coils; its value is
// not used (every covered pass adds a). An additive family
// (TermFamily::additive).
#include <cmath>
#include <string>

#include "core/model/covariates.h"
#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

// The largest wear per coil a fit may give, µm: several times the whole
// wear of an average pass of a hot strip finishing stand (1-3 µm).
constexpr double kMaxUmPerCoil = 20.0;

class PerCoil final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kPerCoil; }
  const char* name() const override { return "per_coil"; }
  TermParamView Param(int /*j*/, double x) const override {
    return {"a (µm per coil)", x};
  }
  bool offered_scoped() const override { return true; }
  bool additive() const override { return true; }
  bool names_mechanism() const override { return true; }
  // a = 0 is the law alone; the upper bound is a bracket.
  bool BoundIsALimit(int j, bool upper) const override {
    return j == 0 && !upper;
  }
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (c.spec->source != CovariateSource::kCoilsBefore) return;
    // Wear is not negative: a in [0, kMaxUmPerCoil], from a = 0 (the law
    // alone, where the diagnosis's score screen tests it; one parameter
    // entering linearly needs no other start).
    out->push_back(Proposal(*this, c, {0.0}, {0.0}, {kMaxUmPerCoil}));
  }
  double Evaluate(const ModelTerm& t, double /*z*/,
                  double* grad) const override {
    if (grad != nullptr) grad[0] = 1.0;
    return t.params[0];
  }
  void RefitBounds(const ModelTerm& /*t*/, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    *lo = {0.0};
    *hi = {kMaxUmPerCoil};
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    out->up = t.params[0] > 0;
    out->shape = "constant_per_coil";
    out->parameters = {{"um_per_coil", t.params[0]}};
    const double se = StdErrorOf(in, 0);
    out->fitted =
        WordFormat("%.3g µm of wear per coil", t.params[0]) +
        (std::isfinite(se) ? WordFormat(" (standard error %.2g)", se) : "") +
        " on each roll it covers, whatever the coil's length and load";
    out->mechanism = "wear_per_coil";
    out->mechanism_text =
        "Each coil wears the roll by a fixed amount whatever its length and "
        "load (the impact of the bite at threading, the strip's head and "
        "tail): wear grows with the number of coils, which the wear law, "
        "proportional to the rolled length under load, leaves out.";
  }
  std::optional<TermFieldError> CheckStored(const ModelTerm& t) const override {
    if (std::optional<TermFieldError> e = TermFamily::CheckStored(t)) return e;
    if (t.covariate != "campaign_coils_before") {
      return TermFieldError{"covariate",
                            "must be campaign_coils_before for the per_coil "
                            "form (wear added per coil)"};
    }
    if (!t.params.empty() && !(t.params[0] >= 0)) {
      return TermFieldError{"params",
                            "must be >= 0 µm per coil for the "
                            "per_coil form (wear is not negative)"};
    }
    return std::nullopt;
  }
};

}  // namespace

const TermFamily& PerCoilFamily() {
  static const PerCoil family;
  return family;
}

}  // namespace rollwear
