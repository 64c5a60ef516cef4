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
  bool measurement() const override { return true; }
  int NumParams(const ModelTerm& /*t*/) const override { return 2; }
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
