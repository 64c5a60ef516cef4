// The saturating family: m = 1 + b (1 - exp(-z / lam)), lam = exp(q):
// growth that levels off after a few lam; linear growth is the lam >> z
// limit (a wear-rate term, model_terms.h).
#include <cmath>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Saturating final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kSaturating; }
  const char* name() const override { return "saturating"; }
  TermParamView Param(int j, double x) const override {
    return j == 0 ? TermParamView{"b", x} : TermParamView{"lam", std::exp(x)};
  }
  // Every bound is a limit of the shape: a line (b and lam large together,
  // b / lam the slope: linear growth fitted as b = 10 with lam far beyond
  // the data, stoppages seed 105), a step (lam small), no effect below
  // m = 0.1.
  bool BoundIsALimit(int /*j*/, bool /*upper*/) const override { return true; }
  int NumParams(const ModelTerm& /*t*/) const override { return 2; }
  // Over a quantity that grows within a campaign (rolled length, coils,
  // hours); lam starts at the 95th percentile and is tried at 1/5 and 5
  // times it.
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!GrowsWithinCampaign(c)) return;
    TermProposal p =
        Proposal(*this, c, {0.0, std::log(c.p95)},
                 {-0.9, std::log(0.05 * c.p95)}, {10.0, std::log(20 * c.p95)});
    for (double f : {0.2, 1.0, 5.0})
      p.starts.push_back({0.0, std::log(f * c.p95)});
    out->push_back(std::move(p));
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double b = t.params[0];
    const double lam = std::exp(t.params[1]);
    const double e = std::exp(-z / lam);
    if (grad != nullptr) {
      grad[0] = 1 - e;
      grad[1] = -b * e * (z / lam);  // d/dq of -b e, q = log lam
    }
    return 1 + b * (1 - e);
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

const TermFamily& SaturatingFamily() {
  static const Saturating family;
  return family;
}

}  // namespace rollwear
