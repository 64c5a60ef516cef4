// The offset-per-level family: the grinder reads y = d + d_l for level
// l != r of a measurement-side text column (r = reference_level, chosen by
// the fit; params in level order without r): a second grinder, a gauge, a
// shift crew reading differently (a measurement term, model_terms.h).
#include <algorithm>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class OffsetPerLevel final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kOffsetPerLevel; }
  const char* name() const override { return "offset_per_level"; }
  bool measurement() const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return std::max(0, t.num_levels - 1);
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const int l = static_cast<int>(z);
    if (l < 0 || l >= t.num_levels || l == t.reference_level) return 0.0;
    const int j = l < t.reference_level ? l : l - 1;
    if (grad != nullptr) grad[j] = 1.0;
    return t.params[j];
  }
  void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    SymmetricBounds(NumParams(t), 1000.0, lo, hi);
  }
  std::optional<TermFieldError> CheckStored(const ModelTerm& t) const override {
    // The reference level indexes the levels (Evaluate skips it): out of
    // range it would move every offset onto another level.
    if (t.reference_level < 0 ||
        t.reference_level >= std::max(1, t.num_levels)) {
      return TermFieldError{"reference_level",
                            "must be a level index below num_levels"};
    }
    ModelTerm shared = t;
    shared.reference_level = 0;
    return TermFamily::CheckStored(shared);
  }
};

}  // namespace

const TermFamily& OffsetPerLevelFamily() {
  static const OffsetPerLevel family;
  return family;
}

}  // namespace rollwear
