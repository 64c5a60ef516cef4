// The log-linear family: m = exp(b (z - c) / s), c and s the training mean
// and sd of the covariate, so b is the log-change of the wear rate per
// standard deviation (a wear-rate term, model_terms.h).
#include <cmath>
#include <tuple>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class LogLinear final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kLogLinear; }
  const char* name() const override { return "log_linear"; }
  TermParamView Param(int /*j*/, double x) const override {
    return {"b (log-change per sd)", x};
  }
  bool offered_scoped() const override { return true; }
  bool exponential() const override { return true; }
  double Exponent(const ModelTerm& t, double z) const override {
    return (z - t.center) / t.scale;
  }
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, false)) return;
    out->push_back(Proposal(*this, c, {0.0}, {-2.0}, {2.0}));
    out->back().term.center = c.mean;
    out->back().term.scale = c.sd;
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double u = Exponent(t, z);
    const double m = std::exp(t.params[0] * u);
    if (grad != nullptr) grad[0] = m * u;
    return m;
  }
  void RefitBounds(const ModelTerm& /*t*/, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    *lo = {-2.0};
    *hi = {2.0};
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    std::tie(out->shape, out->up) = in.profile_shape();
    out->parameters = {
        {"beta", t.params[0]}, {"center", t.center}, {"scale", t.scale}};
    out->fitted = in.range_text;
  }
};

}  // namespace

const TermFamily& LogLinearFamily() {
  static const LogLinear family;
  return family;
}

}  // namespace rollwear
