// The flag family: m = exp(b z) for z in {0, 1}, a wear rate exp(b) times
// as high when the flag is on (a wear-rate term, model_terms.h).
#include <cmath>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Flag final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kFlag; }
  const char* name() const override { return "flag"; }
  TermParamView Param(int /*j*/, double x) const override {
    return {"multiplier when on exp(b)", std::exp(x)};
  }
  bool offered_scoped() const override { return true; }
  bool offered_gated() const override { return true; }
  bool exponential() const override { return true; }  // u = z
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (c.spec->kind == CovariateKind::kFlag)
      out->push_back(Proposal(*this, c, {0.0}, {-3.0}, {3.0}));
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double m = std::exp(t.params[0] * z);
    if (grad != nullptr) grad[0] = m * z;
    return m;
  }
  void Word(const ModelTerm& t, const TermWordingInput& /*in*/,
            TermWording* out) const override {
    out->up = t.params[0] > 0;
    out->shape = out->up ? "higher_when_on" : "lower_when_on";
    out->parameters = {{"beta", t.params[0]},
                       {"multiplier_on", std::exp(t.params[0])}};
    out->fitted =
        WordFormat("wear-rate multiplier %.3f when on", std::exp(t.params[0]));
  }
};

}  // namespace

const TermFamily& FlagFamily() {
  static const Flag family;
  return family;
}

}  // namespace rollwear
