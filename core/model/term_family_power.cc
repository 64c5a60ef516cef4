// The power family: m = (z / c)^b for z > 0, c the training median, so a
// wear rate proportional to z^b (a wear-rate term, model_terms.h).
#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Power final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kPower; }
  const char* name() const override { return "power"; }
  TermParamView Param(int /*j*/, double x) const override {
    return {"exponent b", x};
  }
  bool exponential() const override { return true; }
  double Exponent(const ModelTerm& t, double z) const override {
    return std::log(std::max(z, 1e-12) / t.center);
  }
  // Only over a positive covariate; the reference c is its mean.
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, false) || !(c.p01 > 0)) return;
    out->push_back(Proposal(*this, c, {0.0}, {-4.0}, {4.0}));
    out->back().term.center = c.mean;
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double lz = Exponent(t, z);
    const double m = std::exp(t.params[0] * lz);
    if (grad != nullptr) grad[0] = m * lz;
    return m;
  }
  void RefitBounds(const ModelTerm& /*t*/, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    *lo = {-4.0};
    *hi = {4.0};
  }
  std::optional<TermFieldError> CheckStored(const ModelTerm& t) const override {
    if (!(t.center > 0)) {
      return TermFieldError{"center",
                            "must be > 0 for the power form (z / center)^b"};
    }
    return TermFamily::CheckStored(t);
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    std::tie(out->shape, out->up) = in.profile_shape();
    out->parameters = {{"exponent", t.params[0]}, {"reference", t.center}};
    out->fitted = in.range_text;
  }
};

}  // namespace

const TermFamily& PowerFamily() {
  static const Power family;
  return family;
}

}  // namespace rollwear
