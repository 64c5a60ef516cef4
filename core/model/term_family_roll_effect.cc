// The roll-effect family: m = exp(b_r) for the physical roll r (covariate
// roll_id, levels = roll ids, one parameter per roll, no reference): the
// roll's own wear resistance, a random effect with the normal prior
// b_r ~ N(0, s^2), s = `scale` estimated from the data (core/fit/
// roll_effects.h: DerSimonian & Laird 1986). A roll the fit never saw
// counts as 1, its type's value (a wear-rate term, model_terms.h).
#include <algorithm>
#include <cmath>

#include "core/model/covariates.h"
#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class RollEffect final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kRollEffect; }
  const char* name() const override { return "roll_effect"; }
  bool scales_added_wear() const override { return true; }
  // One parameter per level or bin: a sparse one may sit at its bracket
  // while the term is sound; the box check reads single-shape families.
  bool BoundIsALimit(int /*j*/, bool /*upper*/) const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return std::max(0, t.num_levels);
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const int l = static_cast<int>(z);
    if (l < 0 || l >= t.num_levels) return 1.0;
    const double m = std::exp(t.params[l]);
    if (grad != nullptr) grad[l] = m;
    return m;
  }
  double PriorSd(const ModelTerm& t) const override { return t.scale; }
  std::optional<TermFieldError> CheckStored(const ModelTerm& t) const override {
    if (t.covariate != kRollIdName) {
      return TermFieldError{"form",
                            "roll_effect is the form of covariate "
                            "roll_id, and roll_id takes no other"};
    }
    const size_t n = static_cast<size_t>(std::max(0, t.num_levels));
    if (t.levels.size() != n || t.params.size() != n) {
      return TermFieldError{"levels",
                            "a roll_effect term needs one roll id "
                            "and one parameter per level"};
    }
    if (t.reference_level != 0) {
      return TermFieldError{"reference_level",
                            "is only for the offset_per_level form"};
    }
    return std::nullopt;
  }
};

}  // namespace

const TermFamily& RollEffectFamily() {
  static const RollEffect family;
  return family;
}

}  // namespace rollwear
