// The binned family: m = exp(b_k) for z in quantile bin k >= 1 of the
// training data (bin 0: m = 1; `edges` the upper edges of bins 0..B-2): a
// wear-rate multiplier of any shape (a wear-rate term, model_terms.h).
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "core/model/term_family.h"
#include "core/model/term_family_list.h"

namespace rollwear {
namespace {

// The bin j whose jump from bin j - 1 carries at least 3/4 of a binned
// profile's total change, every other jump at most 1/4 of it (a step seen
// through quantile bins, such as a wear rate 1.21 times higher from the
// third regrind on: bins 1.000, 1.208, 1.198, 1.212); 0 when there is none.
int SingleJump(const std::vector<double>& m) {
  const double total = std::abs(m.back() - m.front());
  size_t j = 0;
  double largest = 0;
  for (size_t i = 1; i < m.size(); ++i) {
    if (std::abs(m[i] - m[i - 1]) > largest) {
      largest = std::abs(m[i] - m[i - 1]);
      j = i;
    }
  }
  if (!(total > 0) || largest < 0.75 * total) return 0;
  for (size_t i = 1; i < m.size(); ++i) {
    if (i != j && std::abs(m[i] - m[i - 1]) > 0.25 * largest) return 0;
  }
  return static_cast<int>(j);
}

class Binned final : public TermFamily {
 public:
  TermForm form() const override { return TermForm::kBinned; }
  const char* name() const override { return "binned"; }
  // One parameter per level or bin: a sparse one may sit at its bracket
  // while the term is sound; the box check reads single-shape families.
  bool BoundIsALimit(int /*j*/, bool /*upper*/) const override { return true; }
  int NumParams(const ModelTerm& t) const override {
    return static_cast<int>(t.edges.size());
  }
  void Propose(const CovariateSummary& c,
               std::vector<TermProposal>* out) const override {
    if (!NumericOn(c, false) || c.edges.size() < 2 || !(c.edges.back() < c.max))
      return;
    const size_t nb = c.edges.size();
    out->push_back(Proposal(*this, c, std::vector<double>(nb, 0.0),
                            std::vector<double>(nb, -3.0),
                            std::vector<double>(nb, 3.0)));
    out->back().term.edges = c.edges;
  }
  double Evaluate(const ModelTerm& t, double z, double* grad) const override {
    const int b = TermBin(t, z);
    if (b == 0) return 1.0;
    const double m = std::exp(t.params[b - 1]);
    if (grad != nullptr) grad[b - 1] = m;
    return m;
  }
  void Word(const ModelTerm& t, const TermWordingInput& in,
            TermWording* out) const override {
    std::tie(out->shape, out->up) = in.profile_shape();
    std::vector<double> m = {1.0};
    for (double b : t.params) m.push_back(std::exp(b));
    for (size_t i = 0; i < m.size(); ++i) {
      out->parameters["bin" + std::to_string(i) + "_multiplier"] = m[i];
    }
    for (size_t i = 0; i < t.edges.size(); ++i) {
      out->parameters["edge" + std::to_string(i)] = t.edges[i];
    }
    if (t.edges.size() == 1) {  // a change point (the diagnosis's steps)
      out->shape = m[1] >= 1 ? "step_up" : "step_down";
      out->fitted =
          WordFormat("a step: wear-rate multiplier %.3f from ", m[1]) +
          in.readable(t.edges[0]) + " on, relative to before";
      return;
    }
    out->fitted = "wear-rate multipliers by quantile bin of the covariate:";
    for (size_t i = 0; i < m.size(); ++i) {
      out->fitted += WordFormat(" %.3f", m[i]);
      if (i < t.edges.size())
        out->fitted += " | " + in.readable(t.edges[i]) + " |";
    }
    if (const int j = SingleJump(m);
        j > 0 && out->shape.rfind("threshold", 0) != 0) {
      out->shape = m[j] > m[j - 1] ? "step_up" : "step_down";
      out->fitted +=
          WordFormat("; a step: %.3f times the rate below ", m[j] / m[j - 1]) +
          in.readable(t.edges[j - 1]) + " from there on";
    }
  }
};

}  // namespace

const TermFamily& BinnedFamily() {
  static const Binned family;
  return family;
}

}  // namespace rollwear
