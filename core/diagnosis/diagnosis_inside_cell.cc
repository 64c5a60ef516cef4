// The proxy guard's look inside a cell (docs/diagnosis.md, "The proxy
// guard", "Inside a cell"): a cell term claims one constant multiplier on
// the passes of its place (a stand or roll position x a roll type or
// grade). An effect that lives on that place but varies with a pass-level
// quantity is taken by the cell as its mean: width acting on roll type X at
// F7 only, (1000/w)^1.2, is fitted as "X at F7 x 0.78", or as its twin "X
// at F6 x 1.28", with p = 1e-37, and the width is never seen, since an
// unscoped or single-scoped width term is inconsistent across the other
// factor and refused. Here each numeric wear-rate covariate (of the pass,
// the roll or the campaign; not a locate-only one) gets a
// log-linear term m = exp(b (z - c) / s) (c, s: the training mean and sd)
// restricted to the cell's place, and to its twin's (TwinCell, which
// describes the same data), on top of the model that holds the cell. The
// nested likelihood-ratio test LR = n ln(RSS / RSS_inside) ~ chi2(1)
// (Wilks 1938, Ann. Math. Stat. 9:60), Bonferroni over places x
// covariates, at the sibling test's family-wise level (the burden of proof
// is on the cell's "constant"), asks whether the cell's effect varies with
// the covariate there. When it does, and the same term over every pass does
// not explain as much (an effect of the whole mill is not the cell's), the
// cell is refused and the place is located along the covariate: the
// vocabulary has no covariate scoped to two factors at once, so the
// mismatch is located, not named.
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// The family-wise level (as the sibling test's, diagnosis_siblings.cc).
constexpr double kInsideAlpha = 0.01;
// The smallest slope worth a refusal: 5 % of wear per sd of the covariate.
constexpr double kMaterialSlope = 0.05;

// `with_term` plus a log-linear term in covariate k over `scope`.
Fitted FitInside(const DiagnosisState& st, const std::vector<double>& sd,
                 const Fitted& with_term, int k, double mean, double spread,
                 const TermScope& scope) {
  TermSpec s;
  s.covariate = k;
  s.term.covariate = st.td.catalog[k].name;
  s.term.form = TermForm::kLogLinear;
  s.term.params = {0.0};
  s.term.center = mean;
  s.term.scale = spread;
  s.term.scope = scope;
  s.lower = {-2.0};
  s.upper = {2.0};
  std::vector<TermSpec> terms = with_term.terms;
  terms.push_back(s);
  return Fit(st.td, st.train, sd, with_term.log_k, terms);
}

double LogRatio(double n, double rss_a, double rss_b) {
  return std::max(0.0, n * std::log(rss_a / rss_b));
}

// The training readings' mean residual inside `scope` under `fitted`.
double MeanResidualIn(const DiagnosisState& st, const Fitted& fitted,
                      const TermScope& scope) {
  const std::vector<double> pred =
      PredictTerms(st.td, st.train, fitted.log_k, fitted.terms);
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < st.train.size(); ++i) {
    const TermObservation& ob = st.td.obs[st.train[i]];
    if (!InScope(st.td, ob, scope)) continue;
    sum += ob.measured_um - pred[i];
    ++count;
  }
  return count > 0 ? sum / count : 0;
}

}  // namespace

GuardResult LookInsideCell(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd,
                           const Fitted& with_term) {
  GuardResult r;
  const TermSpec& cell = with_term.terms.back();
  if (cell.term.form != TermForm::kCell) return r;
  std::vector<TermScope> places = {cell.term.scope};
  TermScope twin;
  if (TwinCell(st.td, st.train, cell.term.scope, &twin)) places.push_back(twin);
  std::vector<int> covariates;
  for (int k = 0; k < static_cast<int>(st.td.catalog.size()); ++k) {
    const CovariateSpec& c = st.td.catalog[k];
    if (c.level != CovariateLevel::kMeasurement &&
        c.kind == CovariateKind::kNumeric &&
        c.source != CovariateSource::kCell && !c.locate_only) {
      covariates.push_back(k);
    }
  }
  const double tests = static_cast<double>(places.size() * covariates.size());
  const double n = static_cast<double>(st.train.size());
  double best_p = 1, best_lr = 0, best_slope = 0;
  int best_k = -1;
  const TermScope* best_place = nullptr;
  for (int k : covariates) {
    double mean = 0, spread = 0;
    const WeightedValues w = Collect(st.td, st.train, k);
    if (!(w.total > 0)) continue;
    MeanSd(w, &mean, &spread);
    if (!(spread > 0)) continue;
    for (const TermScope& place : places) {
      const Fitted inside =
          FitInside(st, sd, with_term, k, mean, spread, place);
      if (!inside.usable || !(inside.rss > 0)) continue;
      const double slope = inside.terms.back().term.params[0];
      const double lr = LogRatio(n, with_term.rss, inside.rss);
      const double p = ChiSquareSurvival(lr, 1);
      if (std::abs(slope) < kMaterialSlope || p >= best_p) continue;
      // An effect of every pass is not the cell's: the same term over the
      // whole mill must explain less.
      const Fitted everywhere =
          FitInside(st, sd, with_term, k, mean, spread, TermScope{});
      if (everywhere.usable && everywhere.rss <= inside.rss) continue;
      best_p = p;
      best_lr = lr;
      best_slope = slope;
      best_k = k;
      best_place = &place;
    }
  }
  if (best_place == nullptr ||
      !(best_p * tests < std::max(kInsideAlpha, options.alpha))) {
    return r;
  }
  const std::string& name = st.td.catalog[best_k].name;
  char buf[320];
  std::snprintf(buf, sizeof(buf),
                "not constant inside the cell: on %s the effect varies with "
                "%s (%+.0f %% per sd; LR %.1f, p adjusted %.2g), and no "
                "covariate term is scoped to a stand and a %s at once",
                best_place->Label().c_str(), name.c_str(),
                100 * (std::exp(best_slope) - 1), best_lr,
                std::min(1.0, best_p * tests),
                cell.term.scope.roll_type.empty() ? "grade" : "roll type");
  r.pass = false;
  r.reason = buf;
  r.located.dimension = "effect_by_" + name;
  r.located.where = best_place->Label() + ": along " + name;
  r.located.test = "likelihood_ratio";
  r.located.statistic = best_lr;
  r.located.mean_residual_um = MeanResidualIn(st, with_term, *best_place);
  r.located.p_value = best_p;
  r.located.p_adjusted = std::min(1.0, best_p * tests);
  return r;
}

}  // namespace rollwear::diag
