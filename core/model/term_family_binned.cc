// The binned family: m = exp(b_k) for z in quantile bin k >= 1 of the
// training data (bin 0: m = 1; `edges` the upper edges of bins 0..B-2): a
// wear-rate multiplier of any shape (a wear-rate term, model_terms.h).
#include <cmath>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class Binned final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kBinned; }
  const char* name() const override { return "binned"; }
  int NumParams(const ModelTerm& t) const override {
    return static_cast<int>(t.edges.size());
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const int b = TermBin(t, z);
    if (b == 0) return 1.0;
    const double m = std::exp(t.params[b - 1]);
    if (grad != nullptr) grad[b - 1] = m;
    return m;
  }
};

}  // namespace

const TermFamily& BinnedFamily() {
  static const Binned family;
  return family;
}

}  // namespace rollwear
