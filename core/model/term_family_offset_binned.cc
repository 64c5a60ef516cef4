// The offset-binned family: the grinder reads y = d + A_k in quantile bin
// k >= 1 of z (bin 0 reads as is; edges as the binned family): a gauge that
// steps or drifts unevenly over calendar time (a measurement term,
// model_terms.h).
#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class OffsetBinned final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kOffsetBinned; }
  const char* name() const override { return "offset_binned"; }
  bool measurement() const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return static_cast<int>(t.edges.size());
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const int b = TermBin(t, z);
    if (b == 0) return 0.0;  // the first bin reads as is
    if (grad != nullptr) grad[b - 1] = 1.0;
    return t.params[b - 1];
  }
  void RefitBounds(const ModelTerm& t, std::vector<double>* lo,
                   std::vector<double>* hi) const override {
    SymmetricBounds(NumParams(t), 1000.0, lo, hi);
  }
};

}  // namespace

const TermFamily& OffsetBinnedFamily() {
  static const OffsetBinned family;
  return family;
}

}  // namespace rollwear
