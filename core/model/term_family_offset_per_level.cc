// The offset-per-level family: the grinder reads y = d + d_l for level
// l != r of a measurement-side text column (r = reference_level, chosen by
// the fit; params in level order without r): a second grinder, a gauge, a
// shift crew reading differently (a measurement term, model_terms.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class OffsetPerLevel final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kOffsetPerLevel; }
  const char* name() const override { return "offset_per_level"; }
  // One parameter per level or bin: a sparse one may sit at its bracket
  // while the term is sound; the box check reads single-shape families.
  bool BoundIsALimit(int /*j*/, bool /*upper*/) const override { return true; }
  bool measurement() const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return std::max(0, t.num_levels - 1);
  }
  // One candidate per reference level with readings: which level reads
  // true is identified by the wear law itself (wear is proportional to the
  // load, with no intercept, so a constant offset on every reading cannot
  // be absorbed by K), and the tests choose, so that the odd gauge out is
  // the one named (not the majority, relative to a minority).
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (c.spec->kind != CovariateKind::kFactor ||
        c.spec->level != CovariateLevel::kMeasurement) {
      return;
    }
    for (int ref = 0; ref < c.levels; ++ref) {
      if (!(c.level_weight[ref] > 0)) continue;
      out->push_back(PerLevelProposal(*this, c, 1000.0));
      out->back().term.reference_level = ref;
    }
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
    return NoRollEffectFields(t);
  }
  // The levels whose offset is significant (|d| > 2 s.e., or every
  // non-reference level without standard errors) and the sentence "the
  // reading of grinder=B is offset by -15.2 µm".
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    out->shape = "offset_per_level";
    out->up = false;
    out->levels.emplace();
    const std::string ref =
        t.reference_level < static_cast<int>(t.levels.size())
            ? t.levels[t.reference_level]
            : "";
    std::string& fitted = out->fitted;
    for (size_t j = 0; j < t.params.size(); ++j) {
      const size_t l = static_cast<int>(j) < t.reference_level ? j : j + 1;
      const std::string label =
          l < t.levels.size() ? t.levels[l] : std::to_string(l);
      out->parameters["offset_um[" + label + "]"] = t.params[j];
      const double se = StdErrorOf(in, j);
      const bool significant =
          !std::isfinite(se) || std::abs(t.params[j]) > 2 * se;
      if (!significant) continue;
      out->levels->push_back(label);
      if (!fitted.empty()) fitted += "; ";
      fitted += "the reading of " + t.covariate + "=" + label +
                WordFormat(" is offset by %+.1f µm", t.params[j]);
    }
    if (fitted.empty()) fitted = "no level's offset is significant";
    fitted += " (reference " + t.covariate + "=" + ref + ")";
  }
};

}  // namespace

const TermFamily& OffsetPerLevelFamily() {
  static const OffsetPerLevel family;
  return family;
}

}  // namespace rollwear
