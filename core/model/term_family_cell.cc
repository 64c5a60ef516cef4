// The cell family: m = exp(b) on the passes of its scope, a (stand or roll
// position) x (roll type or grade) cell the K structure cannot express
// (covariate "cell", always 1), fitted with the prior b ~ N(0, tau^2),
// tau = kCellPriorSd (a wear-rate term, model_terms.h).
#include <cmath>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Cell final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kCell; }
  const char* name() const override { return "cell"; }
  TermParamView Param(int /*j*/, double x) const override {
    return {"multiplier exp(b)", std::exp(x)};
  }
  double Evaluate(const ModelTerm& t, double /*z*/,
                  double* grad) const override {
    const double m = std::exp(t.params[0]);
    if (grad != nullptr) grad[0] = m;
    return m;
  }
  double PriorSd(const ModelTerm& /*t*/) const override { return kCellPriorSd; }
  void Word(const ModelTerm& t, const TermWordingInput& /*in*/,
            TermWording* out) const override {
    out->up = t.params[0] > 0;
    out->shape = out->up ? "higher_in_cell" : "lower_in_cell";
    out->parameters = {{"beta", t.params[0]},
                       {"multiplier", std::exp(t.params[0])}};
    out->fitted = WordFormat("wear-rate multiplier %.3f in the cell",
                             std::exp(t.params[0]));
  }
};

}  // namespace

const TermFamily& CellFamily() {
  static const Cell family;
  return family;
}

}  // namespace rollwear
