// The decaying family: m = 1 + b exp(-z / lam), lam = exp(q): run-in, extra
// wear early on that fades (a wear-rate term, model_terms.h).
#include <cmath>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Decaying final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kDecaying; }
  const char* name() const override { return "decaying"; }
  TermParamView Param(int j, double x) const override {
    return j == 0 ? TermParamView{"b", x} : TermParamView{"lam", std::exp(x)};
  }
  // The length scale's bounds (a step on the first passes; a decline over
  // the whole range) and m >= 0.1 are limits of the shape; b = 10, eleven
  // times the wear rate at the start, is a bracket.
  bool BoundIsALimit(int j, bool upper) const override {
    return j == 1 || !upper;
  }
  int NumParams(const ModelTerm& /*t*/) const override { return 2; }
  // Over a quantity that grows within a campaign; run-in fades early, so
  // lam starts at a tenth of the 95th percentile (tried at 0.02 and 0.4).
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!GrowsWithinCampaign(c)) return;
    TermProposal p =
        Proposal(*this, c, {0.0, std::log(0.1 * c.p95)},
                 {-0.9, std::log(0.005 * c.p95)}, {10.0, std::log(c.p95)});
    for (double f : {0.02, 0.1, 0.4})
      p.starts.push_back({0.0, std::log(f * c.p95)});
    out->push_back(std::move(p));
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double b = t.params[0];
    const double lam = std::exp(t.params[1]);
    const double e = std::exp(-z / lam);
    if (grad != nullptr) {
      grad[0] = e;
      grad[1] = b * e * (z / lam);  // d/dq, q = log lam
    }
    return 1 + b * e;
  }
  void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    AmplitudeAndLogScaleBounds(-0.9, 10.0, t.params[1], lo, hi);
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    WordAmplitudeAndLengthScale(t, in, out);
  }
};

}  // namespace

const TermFamily& DecayingFamily() {
  static const Decaying family;
  return family;
}

}  // namespace rollwear
