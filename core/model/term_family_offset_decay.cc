// The offset-decay family: the grinder reads y = d + A exp(-z / tau),
// tau = exp(q): a reading off by A right after the campaign that fades
// with the time before measuring (a measurement term, model_terms.h).
#include <cmath>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class OffsetDecay final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kOffsetDecay; }
  const char* name() const override { return "offset_decay"; }
  TermParamView Param(int j, double x) const override {
    return j == 0 ? TermParamView{"A (µm)", x}
                  : TermParamView{"tau", std::exp(x)};
  }
  // A short time constant is a step on the first readings, still the
  // shape; a long one is a constant offset on every reading (an intercept,
  // not a drift that fades): a bracket, as the amplitude's +-1000 µm.
  bool BoundIsALimit(int j, bool upper) const override {
    return j == 1 && !upper;
  }
  bool measurement() const override { return true; }
  int NumParams(const ModelTerm& /*t*/) const override { return 2; }
  // tau starts at the median and is tried at 1/4 and 4 times it.
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, true) || !(c.p01 >= 0 && c.p50 > 0)) return;
    TermProposal p = Proposal(*this, c, {0.0, std::log(c.p50)},
                              {-1000.0, std::log(0.02 * c.p50)},
                              {1000.0, std::log(20 * c.p95)});
    for (double f : {0.25, 1.0, 4.0})
      p.starts.push_back({0.0, std::log(f * c.p50)});
    out->push_back(std::move(p));
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double a = t.params[0];
    const double tau = std::exp(t.params[1]);
    const double e = std::exp(-z / tau);
    if (grad != nullptr) {
      grad[0] = e;
      grad[1] = a * e * (z / tau);  // d/dq, q = log tau
    }
    return a * e;
  }
  void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    AmplitudeAndLogScaleBounds(-1000.0, 1000.0, t.params[1], lo, hi);
  }
  void Word(const ModelTerm& t, const TermWordingInput& /*in*/,
            TermWording* out) const override {
    const double a = t.params[0], tau = std::exp(t.params[1]);
    out->up = a > 0;
    out->shape = a < 0 ? "reads_low_when_measured_early"
                       : "reads_high_when_measured_early";
    out->parameters = {{"amplitude_um", a}, {"tau", tau}};
    out->fitted = WordFormat(
        "measured wear offset %.1f µm right after the campaign, fading with "
        "time constant %.3g",
        a, tau);
  }
};

}  // namespace

const TermFamily& OffsetDecayFamily() {
  static const OffsetDecay family;
  return family;
}

}  // namespace rollwear
