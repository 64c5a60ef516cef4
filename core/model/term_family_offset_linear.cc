// The offset-linear family: the grinder reads y = d + A (z - c) / s, c and
// s the training mean and sd: a gauge that drifts with z (a measurement
// term, model_terms.h).
#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class OffsetLinear final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kOffsetLinear; }
  const char* name() const override { return "offset_linear"; }
  TermParamView Param(int /*j*/, double x) const override {
    return {"A (µm per sd)", x};
  }
  bool measurement() const override { return true; }
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, true)) return;
    out->push_back(Proposal(*this, c, {0.0}, {-1000.0}, {1000.0}));
    out->back().term.center = c.mean;
    out->back().term.scale = c.sd;
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const double u = (z - t.center) / t.scale;
    if (grad != nullptr) grad[0] = u;
    return t.params[0] * u;
  }
  void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    SymmetricBounds(NumParams(t), 1000.0, lo, hi);
  }
  void Word(const ModelTerm& t, const TermWordingInput& /*in*/,
            TermWording* out) const override {
    out->up = t.params[0] > 0;
    out->shape = out->up ? "increasing" : "decreasing";
    out->parameters = {{"slope_um_per_sd", t.params[0]},
                       {"center", t.center},
                       {"scale", t.scale}};
    out->fitted = WordFormat(
        "measured wear offset of %.1f µm per standard deviation (%.4g)",
        t.params[0], t.scale);
  }
};

}  // namespace

const TermFamily& OffsetLinearFamily() {
  static const OffsetLinear family;
  return family;
}

}  // namespace rollwear
