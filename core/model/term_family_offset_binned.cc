// The offset-binned family: the grinder reads y = d + A_k in quantile bin
// k >= 1 of z (bin 0 reads as is; edges as the binned family): a gauge that
// steps or drifts unevenly over calendar time (a measurement term,
// model_terms.h).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

class OffsetBinned final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kOffsetBinned; }
  const char* name() const override { return "offset_binned"; }
  // One parameter per level or bin: a sparse one may sit at its bracket
  // while the term is sound; the box check reads single-shape families.
  bool BoundIsALimit(int /*j*/, bool /*upper*/) const override { return true; }
  bool measurement() const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return static_cast<int>(t.edges.size());
  }
  // A reading that steps or drifts unevenly: one offset per quantile bin.
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, true) || c.edges.size() < 2 || !(c.edges.back() < c.max))
      return;
    const size_t nb = c.edges.size();
    out->push_back(Proposal(*this, c, std::vector<double>(nb, 0.0),
                            std::vector<double>(nb, -1000.0),
                            std::vector<double>(nb, 1000.0)));
    out->back().term.edges = c.edges;
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
  // Offsets by quantile bin (bin 0 reads as is): a step when one jump
  // between neighbouring bins carries at least 3/4 of the total change.
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    std::vector<double> o = {0.0};
    for (double b : t.params) o.push_back(b);
    const bool up = o.back() > o.front();
    out->up = up;
    double largest = 0;
    bool monotone = true;
    for (size_t i = 1; i < o.size(); ++i) {
      const double jump = o[i] - o[i - 1];
      largest = std::max(largest, std::abs(jump));
      monotone = monotone && (up ? jump >= -1.0 : jump <= 1.0);  // 1 µm slack
    }
    const double total = std::abs(o.back() - o.front());
    out->shape = !monotone                 ? "uneven"
                 : largest >= 0.75 * total ? (up ? "step_up" : "step_down")
                                           : (up ? "increasing" : "decreasing");
    for (size_t i = 0; i < o.size(); ++i) {
      out->parameters["bin" + std::to_string(i) + "_offset_um"] = o[i];
    }
    for (size_t i = 0; i < t.edges.size(); ++i) {
      out->parameters["edge" + std::to_string(i)] = t.edges[i];
    }
    if (t.edges.size() == 1) {  // a change point (the diagnosis's steps)
      out->fitted =
          WordFormat("a step: measured wear offset %+.1f µm from ", o[1]) +
          in.readable(t.edges[0]) + " on, relative to before";
      return;
    }
    out->fitted =
        "measured wear offsets by quantile bin of the covariate (µm):";
    for (size_t i = 0; i < o.size(); ++i) {
      out->fitted += WordFormat(" %+.1f", o[i]);
      if (i < t.edges.size())
        out->fitted += " | " + in.readable(t.edges[i]) + " |";
    }
  }
};

}  // namespace

const TermFamily& OffsetBinnedFamily() {
  static const OffsetBinned family;
  return family;
}

}  // namespace rollwear
