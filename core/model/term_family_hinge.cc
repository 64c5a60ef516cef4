// The hinge family: m = exp(b max(0, (z - k) / s)): the wear rate changes
// only beyond a knee k of the covariate, above it when s > 0, below it when
// s < 0 (|s| the training sd, so b is the log-change per sd beyond the
// knee); on the other side the wear law holds. A threshold, not a trend:
// the scale of colder strip that turns abrasive below some temperature, a
// speed above which the bite slips (a wear-rate term, model_terms.h).
// The knee is fitted (params[1]); at b = 0 the term is 1 whatever k, as the
// saturating family's length scale.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Hinge final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kHinge; }
  const char* name() const override { return "hinge"; }
  TermParamView Param(int j, double x) const override {
    return j == 0 ? TermParamView{"b (log-change per sd beyond the knee)", x}
                  : TermParamView{"knee", x};
  }
  // Every bound is a bracket: a knee stopped at the edge of the data is
  // the log-linear form over it at the near edge, and at the far edge a
  // term on the last few percent of the passes that wants to go on: either
  // way not a knee the data show (at_box_bound locates it). The
  // amplitude's bounds are brackets too.
  bool SignedScale() const override { return true; }
  int NumParams(const ModelTerm& /*t*/) const override { return 2; }
  // Over a numeric covariate: a knee above which (and one below which) the
  // rate changes, the knee in the 5th..95th percentiles, fitted from two
  // starts, a quarter and three quarters of the way from the 5th to the
  // 95th (the proposal's median is its term, not a start). Not over a
  // quantity that grows within a campaign (rolled length, coils, hours):
  // growth along the campaign is the saturating, decaying and log-linear
  // families' (a knee there would compete with them for one mechanism).
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, false) || GrowsWithinCampaign(c) || !(c.sd > 0)) return;
    const double p25 = c.p05 + 0.25 * (c.p95 - c.p05) / 0.9;
    const double p75 = c.p95 - 0.25 * (c.p95 - c.p05) / 0.9;
    for (double side : {1.0, -1.0}) {
      TermProposal p =
          Proposal(*this, c, {0.0, c.p50}, {-3.0, c.p05}, {3.0, c.p95});
      p.term.scale = side * c.sd;
      for (double k : {p25, p75}) p.starts.push_back({0.0, k});
      out->push_back(std::move(p));
    }
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double b = t.params[0];
    const double u = std::max(0.0, (z - t.params[1]) / t.scale);
    const double m = std::exp(b * u);
    if (grad != nullptr) {
      grad[0] = m * u;
      grad[1] = u > 0 ? -b * m / t.scale : 0.0;
    }
    return m;
  }
  // b in [-3, 3]; the knee within 3 sd of the adopted one.
  void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    const double w = 3 * std::abs(t.scale);
    *lo = {-3.0, t.params[1] - w};
    *hi = {3.0, t.params[1] + w};
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    // The shape over the covariate's 5th..95th percentiles, as for any
    // multiplier; whether it rises with the covariate from the parameters
    // (the hinge is monotone: above the knee with b > 0, or below it with
    // b < 0), not from the profile, which is flat when the knee lies past
    // the 95th (or before the 5th) percentile. The knee's side and place
    // are in the parameters and the sentence.
    std::tie(out->shape, out->up) = in.profile_shape();
    out->up = (t.params[0] > 0) == (t.scale > 0);
    out->parameters = {
        {"beta", t.params[0]}, {"knee", t.params[1]}, {"scale", t.scale}};
    out->fitted = std::string(t.params[0] > 0 ? "the wear rate rises "
                                              : "the wear rate falls ") +
                  (t.scale > 0 ? "above " : "below ") +
                  in.readable(t.params[1]) +
                  " and holds the law on the other side; " + in.range_text;
  }
  std::optional<TermFieldError> CheckStored(const ModelTerm& t) const override {
    if (!std::isfinite(t.scale) || t.scale == 0) {
      return TermFieldError{
          "scale",
          "must be a finite number other than 0 for the hinge form "
          "exp(b max(0, (z - knee) / scale))"};
    }
    return TermFamily::CheckStored(t);
  }
};

}  // namespace

const TermFamily& HingeFamily() {
  static const Hinge family;
  return family;
}

}  // namespace rollwear
