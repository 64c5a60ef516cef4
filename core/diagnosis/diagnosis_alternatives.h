// Internal to core/diagnosis: alternatives to a round's winner, one
// interface for every guard that asks whether another description of the
// mismatch does as well (docs/diagnosis.md, "Alternatives to a winner").
// An alternative is a term added to a model: a factor cell of the round
// (NoBetterThanCell), a rival covariate or another gate
// (diagnosis_rivals.cc), the same term at a sibling level or on a part of
// its scope (diagnosis_siblings.cc), another cell of a cell's kind
// (diagnosis_complement.cc), a slope inside a cell
// (diagnosis_inside_cell.cc), the ungated twin of a gated term
// (diagnosis_gates.cc), the rolls' own scatter
// (diagnosis_look_again.cc).
//
// One test decides them (the rolls' test divides its LR by the campaign
// design effect first), the encompassing test (Mizon & Richard 1986,
// Econometrica 54:657): one description's term added to the model that
// holds the other, the nested likelihood ratio
// LR = n ln(RSS_base / RSS_base+term) ~ chi2(df_term) (Wilks 1938, Ann.
// Math. Stat. 9:60). A guard reads it in the direction its claim needs (the
// alternative added to the winner's model: "does the alternative carry
// something the winner does not?"; the winner added to the alternative's:
// "does the winner carry something the alternative does not?"), or both.
//
// One multiplicity policy decides how many such tests a claim may lose:
//  - a claim refuted when ANY of k tests rejects (a sibling, a part, a
//    slope inside the cell adds) is a union-intersection test: Bonferroni
//    over the k, family-wise at the level (AnyOf);
//  - a claim that needs EVERY test to reject (the winner adds to each
//    rival; each rival explanation of a slope leaves it; each part is
//    required) is an intersection-union test: each at the level, with no
//    correction, which already bounds the chance of a wrong claim (Berger
//    1982, Technometrics 24:295) (EachOf);
//  - the level is thresholds.alternative_alpha, looser than the round's
//    alpha on purpose: the winner has passed the round already, and the
//    question is only whether the data prefer it to an alternative
//    (DiagnosisOptions::IsValid refuses a level below alpha). A test of the
//    winner's own effect again beside an alternative (given the cell, beside
//    the rolls) is one of the round's tests: the round's alpha, Bonferroni
//    over the round's tests (RoundFamily).
//
// Thread-safety: reentrant (reads its arguments only).
#ifndef ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_ALTERNATIVES_H_
#define ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_ALTERNATIVES_H_

#include <algorithm>
#include <vector>

#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {

// The multiplicity policy of one question (above): significant when
// p * looks < level.
struct Multiplicity {
  double level = 0;
  double looks = 1;  // the Bonferroni factor
  double Adjusted(double p) const { return std::min(1.0, p * looks); }
  bool Rejects(double p) const { return p * looks < level; }
};

// Any of `k` tests rejecting decides: Bonferroni over k (at least 1) at
// thresholds.alternative_alpha.
Multiplicity AnyOf(const DiagnosisThresholds& thresholds, double k);
// Every test must reject: each at thresholds.alternative_alpha.
Multiplicity EachOf(const DiagnosisThresholds& thresholds);
// The round's own family: options.alpha, Bonferroni over `num_tests` (at
// least 1).
Multiplicity RoundFamily(const DiagnosisOptions& options, double num_tests);

// The encompassing test of one term added to a model: `with` is the model
// with the term (refitted from `base`'s coefficients and the term's
// params); lr and p are 0 and 1 when that fit fails or leaves no residual.
struct Encompassing {
  double lr = 0, p = 1;
  int df = 0;
  Fitted with;
  bool usable() const { return with.usable && with.rss > 0; }
};
Encompassing Encompass(const DiagnosisState& st, const std::vector<double>& sd,
                       const Fitted& base, const TermSpec& term);
// The same test of a model `with` already fitted, `df` parameters beyond
// `base`.
Encompassing Encompassed(const DiagnosisState& st, const Fitted& base,
                         const Fitted& with, int df);

// Of `alternatives`, each a term added to `base`, the one that adds most
// (the smallest p; the first of equals); index -1 when none adds at all
// (no usable fit, or every p 1).
struct StrongestAlternative {
  int index = -1;
  Encompassing test;
};
StrongestAlternative Strongest(const DiagnosisState& st,
                               const std::vector<double>& sd,
                               const Fitted& base,
                               const std::vector<TermSpec>& alternatives);

}  // namespace rollwear::diag

#endif  // ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_ALTERNATIVES_H_
