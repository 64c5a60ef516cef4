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
// A term that passes is named with its scope; UndeterminedSiblings then
// lists the levels the data cannot place on either side: the same term
// there is not significant (the test above) and not ruled out either (the
// LR of the sibling's free copy against a copy tied to the winner's
// parameters is below the 1 % critical value). "Only at DP600" is then stated
// with the grades for which the data cannot tell.
// LookWithinScope looks the other way, at the parts of the scope along the
// other factor (the roll type at each stand it runs at; the stand on each
// of its roll types and grades): a part where the same term adds
// significantly, or of two parts that split the scope one the effect does
// not require, means the scope is not the place ("Within the scope").
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// The factor a single-factor scope restricts (a roll position, stand and
// position together, is one factor: the K structure's place), or "" for a
// scope of two factors.
std::string FactorName(const TermScope& s) {
  // A gate alone: its covariate, whose other side is its one sibling.
  if (!s.gate.empty()) {
    return s.stand == 0 && s.position < 0 && s.roll_type.empty() &&
                   s.grade.empty()
               ? s.gate
               : "";
  }
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
  if (!s.gate.empty()) return (s.gate_above ? ">= " : "< ") + s.GateAtText();
  const std::string pos = s.position < 0 ? ""
                          : s.position == static_cast<int>(Position::kTop)
                              ? "top"
                              : "bottom";
  if (s.stand > 0)
    return "F" + std::to_string(s.stand) + (pos.empty() ? "" : "/" + pos);
  if (!pos.empty()) return pos;
  return s.roll_type.empty() ? s.grade : s.roll_type;
}

// The other levels, with enough data, of the factor that the last term of
// `with_term` is scoped to (a gate's other side); none for cells,
// measurement terms and scopes of two factors.
std::vector<TermScope> Siblings(const DiagnosisState& st,
                                const TermSpec& spec) {
  std::vector<TermScope> siblings;
  const std::string factor = FactorName(spec.term.scope);
  if (spec.term.form == TermForm::kCell || spec.term.IsMeasurementTerm() ||
      factor.empty()) {
    return siblings;
  }
  if (!spec.term.scope.gate.empty()) {
    // The other side of the gate: "elsewhere the wear law holds" is its.
    TermScope other = spec.term.scope;
    other.gate_above = !other.gate_above;
    siblings.push_back(other);
    return siblings;
  }
  for (const TermScope& s :
       SingleScopes(st.td, st.train, st.thresholds, true)) {
    if (FactorName(s) == factor && !(s == spec.term.scope))
      siblings.push_back(s);
  }
  return siblings;
}

// A copy of the last term of `with_term` at `sibling`: free, starting
// from no effect, or `tied` to the last term's parameters.
TermSpec SiblingTerm(const Fitted& with_term, const TermScope& sibling,
                     bool tied) {
  TermSpec copy = with_term.terms.back();
  copy.term.scope = sibling;
  for (size_t j = 0; j < copy.term.params.size(); ++j) {
    const double v = copy.term.params[j];
    if (!tied) {
      copy.term.params[j] = 0;
      continue;
    }
    // Ceres wants lower < upper: a band far inside the fit's tolerance.
    copy.lower[j] = v - 1e-9 * (1 + std::abs(v));
    copy.upper[j] = v + 1e-9 * (1 + std::abs(v));
  }
  return copy;
}

// Free copies of the last term of `with_term` at each of `scopes`: the
// alternatives the siblings and parts tests add to it.
std::vector<TermSpec> FreeCopies(const Fitted& with_term,
                                 const std::vector<TermScope>& scopes) {
  std::vector<TermSpec> out;
  for (const TermScope& s : scopes)
    out.push_back(SiblingTerm(with_term, s, false));
  return out;
}

}  // namespace

Fitted FitWith(const DiagnosisState& st, const std::vector<double>& sd,
               const Fitted& base, const TermSpec& extra) {
  std::vector<TermSpec> terms = base.terms;
  terms.push_back(extra);
  return Fit(st.td, st.train, sd, base.log_k, terms);
}

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

GuardResult LookAtSiblings(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd,
                           const Fitted& with_term) {
  GuardResult r;
  const TermSpec& spec = with_term.terms.back();
  const TermScope& scope = spec.term.scope;
  const std::string factor = FactorName(scope);
  const std::vector<TermScope> siblings = Siblings(st, spec);
  if (siblings.empty()) return r;
  // Any sibling that adds refutes "elsewhere the law holds".
  const Multiplicity family =
      AnyOf(options.thresholds, static_cast<double>(siblings.size()));
  const StrongestAlternative a =
      Strongest(st, sd, with_term, FreeCopies(with_term, siblings));
  if (a.index < 0 || !family.Rejects(a.test.p)) return r;
  const TermScope* best = &siblings[a.index];
  const double best_p = a.test.p, best_lr = a.test.lr;
  char buf[240];
  std::snprintf(
      buf, sizeof(buf),
      "not confined to %s: the same term is significant at %s too (LR %.1f, "
      "p adjusted %.2g)",
      scope.Label().c_str(), best->Label().c_str(), best_lr,
      family.Adjusted(best_p));
  r.pass = false;
  r.reason = buf;
  r.located.dimension = "effect_by_" + factor;
  r.located.where = factor + "=" + LevelName(*best);
  r.located.test = "likelihood_ratio";
  r.located.statistic = best_lr;
  // Where the structure the scope leaves out lives.
  r.located.mean_residual_um = MeanResidualIn(st, with_term, *best);
  r.located.p_value = best_p;
  r.located.p_adjusted = family.Adjusted(best_p);
  return r;
}

namespace {

// The parts of a single-factor scope along the other factor (docs/
// diagnosis.md, "Within the scope"): a roll type's or a grade's term at each
// stand it runs at, a stand's term on each roll type and grade it holds,
// each with thresholds.min_part_observations training readings and fewer than
// the scope holds.
std::vector<TermScope> Parts(const DiagnosisState& st, const TermSpec& spec) {
  std::vector<TermScope> parts;
  const std::string factor = FactorName(spec.term.scope);
  if (spec.term.form == TermForm::kCell || spec.term.IsMeasurementTerm() ||
      (factor != "stand" && factor != "roll_type" && factor != "grade")) {
    return parts;
  }
  int whole = 0;
  for (int o : st.train) whole += InScope(st.td, st.td.obs[o], spec.term.scope);
  for (const TermScope& s :
       SingleScopes(st.td, st.train, st.thresholds, true)) {
    TermScope part = spec.term.scope;
    if (factor == "stand") {
      if (s.roll_type.empty() && s.grade.empty()) continue;
      part.roll_type = s.roll_type;
      part.grade = s.grade;
    } else {
      if (s.stand <= 0 || s.position >= 0) continue;
      part.stand = s.stand;
    }
    int in = 0;
    for (int o : st.train) in += InScope(st.td, st.td.obs[o], part);
    if (in >= st.thresholds.min_part_observations && in < whole)
      parts.push_back(part);
  }
  return parts;
}

// Training readings inside `s`.
int CountIn(const DiagnosisState& st, const TermScope& s) {
  int n = 0;
  for (int o : st.train) n += InScope(st.td, st.td.obs[o], s) ? 1 : 0;
  return n;
}

// When the parts do not differ significantly, the whole scope is still
// not established if, of its two parts A and B, the effect at A is not
// required: the term on B alone (moved there, parameters free) against
// free terms on A and on B, LR = n ln(RSS_B / RSS_AB) ~ chi2(params), has
// p at or above 1 % (unadjusted: any part not required refuses, so a
// Bonferroni factor would make refusing easier). Naming the whole scope
// would claim the effect at A on no evidence (width acting on a roll type
// at F7 only, fitted on the roll type at F6 and F7 with p = 1e-7: the F6
// part's LR 4.3): refused, and the effect is located on the scope with the
// part that carries it. Only when A and B split the scope's training
// readings between them (a roll type at two measured stands; grade parts
// of a stand share readings, and a part too small to test leaves a rest).
GuardResult PartNotRequired(const DiagnosisState& st,
                            const std::vector<double>& sd,
                            const Fitted& with_term,
                            const std::vector<TermScope>& parts) {
  GuardResult r;
  const TermSpec& spec = with_term.terms.back();
  // A stand's grade parts share readings (a reading sums several grades).
  const bool by_grade_at_stand =
      FactorName(spec.term.scope) == "stand" &&
      (parts.size() != 2 || parts[0].roll_type.empty() ||
       parts[1].roll_type.empty());
  if (parts.size() != 2 || by_grade_at_stand ||
      CountIn(st, parts[0]) + CountIn(st, parts[1]) !=
          CountIn(st, spec.term.scope)) {
    return r;
  }
  const double n = static_cast<double>(st.train.size());
  const int df = spec.term.NumParams();
  // Naming the whole scope needs every part required.
  const Multiplicity each_part = EachOf(st.thresholds);
  for (int a = 0; a < 2; ++a) {
    const TermScope& carrier = parts[1 - a];
    std::vector<TermSpec> terms = with_term.terms;
    terms.back().term.scope = carrier;
    const Fitted moved = Fit(st.td, st.train, sd, with_term.log_k, terms);
    if (!moved.usable) continue;
    const Encompassing e =
        Encompass(st, sd, moved, SiblingTerm(moved, parts[a], false));
    if (!e.usable()) continue;
    const double lr = e.lr, p = e.p;
    if (each_part.Rejects(p)) continue;  // the effect at part a is needed
    char buf[320];
    std::snprintf(buf, sizeof(buf),
                  "the data cannot tell whether it acts on %s: there the term "
                  "is not required (LR %.1f, p %.2g) and not ruled out, so "
                  "%s cannot be told from %s alone",
                  parts[a].Label().c_str(), lr, p,
                  spec.term.scope.Label().c_str(), carrier.Label().c_str());
    r.pass = false;
    r.reason = buf;
    const bool stand = FactorName(spec.term.scope) == "stand";
    r.located.dimension = stand ? "effect_by_roll_type" : "effect_by_stand";
    r.located.where = spec.term.scope.Label() + ", or " + carrier.Label() +
                      " alone: along " + spec.term.covariate;
    r.located.test = "likelihood_ratio";
    // The effect itself, against the model before the term; the round's
    // adjusted p is the candidate's (GuardedWinner fills it in).
    r.located.statistic = NestedLr(n, st.current.rss, with_term.rss);
    r.located.p_value = ChiSquareSurvival(r.located.statistic, df);
    r.located.p_adjusted = std::numeric_limits<double>::quiet_NaN();
    r.located.mean_residual_um = MeanResidualIn(st, with_term, carrier);
    return r;
  }
  return r;
}

}  // namespace

GuardResult LookWithinScope(const DiagnosisState& st,
                            const DiagnosisOptions& options,
                            const std::vector<double>& sd,
                            const Fitted& with_term) {
  GuardResult r;
  const TermSpec& spec = with_term.terms.back();
  const std::vector<TermScope> parts = Parts(st, spec);
  if (parts.size() < 2) return r;
  // Any part where the effect differs refutes the scope's uniformity.
  const Multiplicity family =
      AnyOf(options.thresholds, static_cast<double>(parts.size()));
  const StrongestAlternative a =
      Strongest(st, sd, with_term, FreeCopies(with_term, parts));
  if (a.index < 0) return r;
  const TermScope* best = &parts[a.index];
  const double best_p = a.test.p, best_lr = a.test.lr;
  if (!family.Rejects(best_p)) return PartNotRequired(st, sd, with_term, parts);
  const std::string other =
      FactorName(spec.term.scope) == "stand"
          ? (best->roll_type.empty() ? "grade" : "roll_type")
          : "stand";
  char buf[240];
  std::snprintf(buf, sizeof(buf),
                "not uniform within %s: the effect differs on %s (LR %.1f, p "
                "adjusted %.2g)",
                spec.term.scope.Label().c_str(), best->Label().c_str(), best_lr,
                family.Adjusted(best_p));
  r.pass = false;
  r.reason = buf;
  r.located.dimension = "effect_by_" + other;
  r.located.where = best->Label() + ": along " + spec.term.covariate;
  r.located.test = "likelihood_ratio";
  r.located.statistic = best_lr;
  r.located.p_value = best_p;
  r.located.p_adjusted = family.Adjusted(best_p);
  return r;
}

void NoteUndeterminedSiblings(const DiagnosisState& st,
                              const std::vector<double>& sd,
                              const Fitted& with_term, Finding* f) {
  const TermSpec& spec = with_term.terms.back();
  const int df = spec.term.NumParams();
  std::vector<std::string> levels;
  for (const TermScope& s : Siblings(st, spec)) {
    const Fitted free =
        FitWith(st, sd, with_term, SiblingTerm(with_term, s, false));
    const Fitted tied =
        FitWith(st, sd, with_term, SiblingTerm(with_term, s, true));
    if (!free.usable || !tied.usable || !(free.rss > 0)) continue;
    // The guard found the free copy not significant (family-wise); the
    // level is undetermined when the tied copy is not rejected either
    // (each level on its own: EachOf).
    if (!EachOf(st.thresholds).Rejects(Encompassed(st, tied, free, df).p))
      levels.push_back(LevelName(s));
  }
  f->scope_undetermined = levels;
  if (levels.empty()) return;
  std::string list = levels[0];
  for (size_t i = 1; i < levels.size(); ++i) {
    list += (i + 1 == levels.size() ? " and " : ", ") + levels[i];
  }
  const bool many = levels.size() > 1;
  const std::string factor = FactorName(spec.term.scope);
  std::string where;
  if (factor == "grade") where = many ? "For grades " : "For grade ";
  if (factor == "roll_type")
    where = many ? "For roll types " : "For roll type ";
  if (factor == "position") where = "For the ";
  if (where.empty()) where = "At ";
  const std::string note = where + list +
                           (factor == "position" ? " rolls" : "") +
                           " the data cannot tell: the same term there is "
                           "neither significant nor ruled out.";
  // "...; elsewhere the wear law holds, but for grades A and B the data
  // cannot tell: ...".
  const std::string elsewhere = std::string(kElsewhereTheLawHolds) + ".";
  const size_t at = f->explanation.find(elsewhere);
  if (at == std::string::npos) {
    f->explanation += " " + note;
    return;
  }
  std::string lower = note;
  lower[0] = static_cast<char>(std::tolower(lower[0]));
  f->explanation.replace(at, elsewhere.size(),
                         std::string(kElsewhereTheLawHolds) + ", but " + lower);
}

}  // namespace rollwear::diag
