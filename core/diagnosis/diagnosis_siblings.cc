// The proxy guard's look at a scope's siblings (docs/diagnosis.md, "The
// proxy guard", "The scope's siblings"): a term scoped to one level of a
// factor (one stand, one position, one roll position, one roll type or one
// grade) claims that the factor's other levels follow the wear law. Each
// other level with enough data gets the same covariate and form added to
// the model that holds the term; the nested likelihood-ratio test
// LR = n ln(RSS / RSS_sibling) ~ chi2(params) (Wilks 1938, Ann. Math. Stat.
// 9:60), Bonferroni over the siblings, asks whether the effect is also
// there. When it is, the effect is not confined to the scope, and the
// vocabulary (one level per scope) cannot say where it is: a hard-grade
// effect found in one grade only, or a calendar drift of the whole mill
// found at F7 only. The term is not named, and the sibling is listed as
// where the mismatch still lives.
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// The family-wise level of the sibling test. Looser than the round's alpha
// on purpose: the test guards a claim ("elsewhere the wear law holds"), so
// the burden of proof is on the scope, and failing it only withholds a name.
constexpr double kSiblingAlpha = 0.01;

// The factor a single-factor scope restricts (a roll position, stand and
// position together, is one factor: the K structure's place), or "" for a
// scope of two factors.
std::string FactorName(const TermScope& s) {
  const bool stand = s.stand > 0, position = s.position >= 0;
  const int what = (s.roll_type.empty() ? 0 : 1) + (s.grade.empty() ? 0 : 1);
  if (stand && position) return what == 0 ? "roll_position" : "";
  if (stand + position + what != 1) return "";
  if (stand) return "stand";
  if (position) return "position";
  return s.roll_type.empty() ? "grade" : "roll_type";
}

// The level of a single-factor scope as a breakdown labels it: "F6",
// "top", "F7/top", "ICDP-S2", "DP600".
std::string LevelName(const TermScope& s) {
  const std::string pos = s.position < 0 ? ""
                          : s.position == static_cast<int>(Position::kTop)
                              ? "top"
                              : "bottom";
  if (s.stand > 0)
    return "F" + std::to_string(s.stand) + (pos.empty() ? "" : "/" + pos);
  if (!pos.empty()) return pos;
  return s.roll_type.empty() ? s.grade : s.roll_type;
}

}  // namespace

GuardResult LookAtSiblings(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd,
                           const Fitted& with_term) {
  GuardResult r;
  const TermSpec& spec = with_term.terms.back();
  const TermScope& scope = spec.term.scope;
  const std::string factor = FactorName(scope);
  if (spec.term.form == TermForm::kCell || spec.term.IsMeasurementTerm() ||
      factor.empty()) {
    return r;
  }
  std::vector<TermScope> siblings;
  for (const TermScope& s : SingleScopes(st.td, st.train, true)) {
    if (FactorName(s) == factor && !(s == scope)) siblings.push_back(s);
  }
  if (siblings.empty()) return r;
  const double k = static_cast<double>(siblings.size());  // Bonferroni
  const double n = static_cast<double>(st.train.size());
  double best_p = 1, best_lr = 0;
  const TermScope* best = nullptr;
  for (const TermScope& s : siblings) {
    std::vector<TermSpec> terms = with_term.terms;
    TermSpec sibling = spec;
    sibling.term.scope = s;
    std::fill(sibling.term.params.begin(), sibling.term.params.end(), 0.0);
    terms.push_back(sibling);
    const Fitted both = Fit(st.td, st.train, sd, with_term.log_k, terms);
    if (!both.usable || !(both.rss > 0)) continue;
    const double lr = std::max(0.0, n * std::log(with_term.rss / both.rss));
    const double p = ChiSquareSurvival(lr, spec.term.NumParams());
    if (p < best_p) {
      best_p = p;
      best_lr = lr;
      best = &s;
    }
  }
  if (best == nullptr || !(best_p * k < std::max(kSiblingAlpha, options.alpha)))
    return r;
  // The mean residual, with the term, of the training readings in the
  // sibling: where the structure the scope leaves out lives.
  const std::vector<double> pred =
      PredictTerms(st.td, st.train, with_term.log_k, with_term.terms);
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < st.train.size(); ++i) {
    const TermObservation& ob = st.td.obs[st.train[i]];
    if (!InScope(st.td, ob, *best)) continue;
    sum += ob.measured_um - pred[i];
    ++count;
  }
  char buf[240];
  std::snprintf(
      buf, sizeof(buf),
      "not confined to %s: the same term is significant at %s too (LR %.1f, "
      "p adjusted %.2g)",
      scope.Label().c_str(), best->Label().c_str(), best_lr,
      std::min(1.0, best_p * k));
  r.pass = false;
  r.reason = buf;
  r.located.dimension = "effect_by_" + factor;
  r.located.where = factor + "=" + LevelName(*best);
  r.located.test = "likelihood_ratio";
  r.located.statistic = best_lr;
  r.located.mean_residual_um = count > 0 ? sum / count : 0;
  r.located.p_value = best_p;
  r.located.p_adjusted = std::min(1.0, best_p * k);
  return r;
}

}  // namespace rollwear::diag
