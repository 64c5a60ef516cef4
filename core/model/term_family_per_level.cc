// The per-level family: m = exp(b_l) for level l >= 1 of a factor (level
// 0 the reference, m = 1); `levels` carries the labels so the daemon can
// match a record's label (a wear-rate term, model_terms.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class PerLevel final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kPerLevel; }
  const char* name() const override { return "per_level"; }
  // One parameter per level or bin: a sparse one may sit at its bracket
  // while the term is sound; the box check reads single-shape families.
  bool BoundIsALimit(int /*j*/, bool /*upper*/) const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return std::max(0, t.num_levels - 1);
  }
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (c.spec->kind == CovariateKind::kFactor &&
        c.spec->level != CovariateLevel::kMeasurement) {
      out->push_back(PerLevelProposal(*this, c, 3.0));
    }
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const int l = static_cast<int>(z);
    if (l <= 0 || l >= t.num_levels) return 1.0;
    const double m = std::exp(t.params[l - 1]);
    if (grad != nullptr) grad[l - 1] = m;
    return m;
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    out->shape = "per_level";
    out->fitted = "wear-rate multipliers";
    out->levels.emplace();
    for (size_t i = 0; i < t.params.size(); ++i) {
      const double m = std::exp(t.params[i]);
      out->parameters["level" + std::to_string(i + 1) + "_multiplier"] = m;
      const std::string label =
          i + 1 < t.levels.size() ? t.levels[i + 1] : std::to_string(i + 1);
      out->fitted += WordFormat(" %.3f", m) + " (" + label + ")";
      // The affected levels (the contract's levels): those whose
      // multiplier is more than 2 standard errors from the reference's 1.
      const double se = StdErrorOf(in, i);
      if (!std::isfinite(se) || std::abs(t.params[i]) > 2 * se) {
        out->levels->push_back(label);
      }
    }
  }
};

}  // namespace

const TermFamily& PerLevelFamily() {
  static const PerLevel family;
  return family;
}

}  // namespace rollwear
