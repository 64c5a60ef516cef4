// A set of adopted stand cells that the data cannot tell from its
// complement (docs/diagnosis.md, "Cell sets at two stands"). In a mill
// measured at two stands s and t, with K by roll position, roll type and
// grade (option 1), the cells of one factor form a two-row table whose
// interaction is identified only up to a constant: roll types A and B
// wearing x m more at s predict every reading exactly as the factor's other
// types that run at both stands wearing x m more at t (ComplementCells). The
// data then prefer the sparser description, and when the complement has no
// more cells than the named set (two of four roll types at F7: an
// independent generator's `two_types_f7`, named as the other two types at
// F6 in 7 of 10 seeds in session 16) neither is identified. The set is
// withdrawn: its findings become runners-up, its terms leave the model
// (refitted without them), and the mismatch is listed as located,
// `stand_by_roll_type` or `stand_by_grade`, naming both descriptions.
// A set whose complement has more cells (one roll type of four at F7, one
// grade of ten) stays named: it is the sparsest description, unless
// another cell of its kind joins one of its cells significantly in the
// final model (WithdrawUnconfinedCell): then the set the rounds adopted is
// incomplete, and that cell is withdrawn and located with its sibling.
// Thread-safety: reentrant (changes only its arguments).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

std::string Levels(const std::vector<TermScope>& cells, bool by_type) {
  std::string out;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) out += i + 1 == cells.size() ? " and " : ", ";
    out += by_type ? cells[i].roll_type : cells[i].grade;
  }
  return out;
}

// Withdraws the stand cells of one factor when their complement is no
// sparser; true when it did. `rounds` holds the round each finding was
// adopted in (aligned with report->findings, erased along with them).
bool WithdrawIfTied(const DiagnosisOptions& options, bool by_type,
                    DiagnosisState* st, DiagnosisReport* report,
                    std::vector<int>* rounds) {
  std::vector<int> index;
  std::vector<TermScope> cells;
  for (size_t i = 0; i < report->findings.size(); ++i) {
    const ModelTerm& t = report->findings[i].term;
    if (t.form != TermForm::kCell || t.scope.stand <= 0 ||
        t.scope.position >= 0 ||
        (by_type ? t.scope.roll_type : t.scope.grade).empty()) {
      continue;
    }
    index.push_back(static_cast<int>(i));
    cells.push_back(t.scope);
  }
  std::vector<TermScope> complement;
  if (!ComplementCells(st->td, st->train, cells, &complement) ||
      complement.size() > cells.size()) {
    return false;
  }
  std::vector<TermSpec> kept;
  for (const TermSpec& t : st->current.terms) {
    const bool withdrawn =
        t.term.form == TermForm::kCell &&
        std::find(cells.begin(), cells.end(), t.term.scope) != cells.end();
    if (!withdrawn) kept.push_back(t);
  }
  const std::vector<double> sd = TermNoiseSd(
      st->td, st->train, st->current.log_k, kept, nullptr, options.robust);
  const Fitted refit = Fit(st->td, st->train, sd, st->current.log_k, kept);
  if (!refit.usable) return false;  // keep what was adopted rather than nothing

  const char* what = by_type ? "roll types " : "grades ";
  const std::string named = what + Levels(cells, by_type) + " at F" +
                            std::to_string(cells.front().stand);
  const std::string twin =
      complement.empty() ? std::string("stand F") +
                               std::to_string(cells.front().stand) + "'s own K"
                         : what + Levels(complement, by_type) + " at F" +
                               std::to_string(complement.front().stand);
  Unexplained u;
  u.dimension = by_type ? "stand_by_roll_type" : "stand_by_grade";
  u.where = named + ", or equally " + twin;
  u.test = "lr";
  u.mean_residual_um = ContributionRmsUm(*st, st->current, refit, cells);
  const std::string reason =
      "withdrawn: " + named + " wearing more predicts every reading as " +
      twin +
      " wearing more (two stands: the stands' and the levels' K take up the "
      "factor); the data cannot tell which";
  for (int i : index) {
    const Finding& f = report->findings[i];
    u.statistic += f.lr;
    u.p_value = std::min(u.p_value, f.p_value);
    u.p_adjusted = std::min(u.p_adjusted, f.p_adjusted);
    report->runners_up.push_back({(*rounds)[i], f.covariate, f.form,
                                  f.p_adjusted, f.cv_mse_ratio, reason});
  }
  for (auto it = index.rbegin(); it != index.rend(); ++it) {
    report->findings.erase(report->findings.begin() + *it);
    rounds->erase(rounds->begin() + *it);
  }
  report->unexplained.push_back(u);
  st->current = refit;
  return true;
}

// The family-wise level of the sibling-cell test (as the scope siblings',
// diagnosis_siblings.cc: it guards the claim "elsewhere the law holds").
constexpr double kSiblingCellAlpha = 0.01;

bool SamePlace(const TermScope& a, const TermScope& b) {
  return a.stand == b.stand && a.position == b.position;
}

// The other offered cells of `cell`'s kind at its place or its twin's
// place, not `held`.
std::vector<TermScope> SiblingCells(const DiagnosisState& st,
                                    const TermScope& cell,
                                    const std::vector<TermScope>& held) {
  TermScope twin = cell;
  TwinCell(st.td, st.train, cell, &twin);
  std::vector<TermScope> out;
  for (const TermScope& c : OfferedCellScopes(st.td, st.train)) {
    if (SameCellKind(c, cell) && (SamePlace(c, cell) || SamePlace(c, twin)) &&
        std::find(held.begin(), held.end(), c) == held.end()) {
      out.push_back(c);
    }
  }
  return out;
}

// Withdraws the first adopted cell that another cell of its kind at its
// place (or its twin's), added to the final model, joins significantly
// (nested LR ~ chi2(1), Wilks 1938; Bonferroni over the siblings, at the
// scope siblings' level): the effect lives in a set of cells of which the
// rounds adopted only part, and the named cell would say "elsewhere the
// law holds" of the rest (an independent generator's two grades wearing F7
// more, named as one of them in 2 of 10 seeds, and 1 of 3 with three
// stands, in session 17). True when it withdrew one. After the rounds, so
// that two true cells both adopted are not refused for each other.
bool WithdrawUnconfinedCell(const DiagnosisOptions& options,
                            const std::vector<TermScope>& held,
                            DiagnosisState* st, DiagnosisReport* report,
                            std::vector<int>* rounds) {
  const std::vector<double> sd =
      TermNoiseSd(st->td, st->train, st->current.log_k, st->current.terms,
                  nullptr, options.robust);
  const Fitted base =
      Fit(st->td, st->train, sd, st->current.log_k, st->current.terms);
  if (!base.usable || !(base.rss > 0)) return false;
  const double n = static_cast<double>(st->train.size());
  const double alpha = std::max(kSiblingCellAlpha, options.alpha);
  for (size_t i = 0; i < report->findings.size(); ++i) {
    const TermScope cell = report->findings[i].term.scope;
    if (report->findings[i].term.form != TermForm::kCell) continue;
    const std::vector<TermScope> siblings = SiblingCells(*st, cell, held);
    const StrongestAddition a =
        StrongestOf(siblings, n, base.rss, 1, [&](const TermScope& s) {
          return FitWith(*st, sd, base, CellTermSpec(st->td, s));
        });
    const double k = static_cast<double>(siblings.size());
    if (a.scope == nullptr || !(a.p * k < alpha)) continue;
    const double p_adjusted = std::min(1.0, a.p * k);
    std::vector<TermSpec> kept;
    for (const TermSpec& t : st->current.terms) {
      if (!(t.term.form == TermForm::kCell && t.term.scope == cell))
        kept.push_back(t);
    }
    const std::vector<double> sd_kept = TermNoiseSd(
        st->td, st->train, st->current.log_k, kept, nullptr, options.robust);
    const Fitted refit =
        Fit(st->td, st->train, sd_kept, st->current.log_k, kept);
    if (!refit.usable) return false;
    char buf[320];
    std::snprintf(buf, sizeof(buf),
                  "withdrawn: not confined to %s: the cell %s joins it "
                  "significantly (LR %.1f, p adjusted %.2g); a set of cells "
                  "of which one named alone would say the rest follow the law",
                  cell.Label().c_str(), a.scope->Label().c_str(), a.lr,
                  p_adjusted);
    const Finding& f = report->findings[i];
    report->runners_up.push_back(
        {(*rounds)[i], f.covariate, f.form, f.p_adjusted, f.cv_mse_ratio, buf});
    Unexplained u;
    u.dimension =
        std::string(cell.position >= 0 ? "position_by_" : "stand_by_") +
        (cell.roll_type.empty() ? "grade" : "roll_type");
    u.where = cell.Label() + " and " + a.scope->Label();
    u.test = "likelihood_ratio";
    u.statistic = a.lr;
    u.p_value = a.p;
    u.p_adjusted = p_adjusted;
    u.mean_residual_um = ContributionRmsUm(*st, st->current, refit, {cell});
    report->unexplained.push_back(u);
    report->findings.erase(report->findings.begin() + i);
    rounds->erase(rounds->begin() + i);
    st->current = refit;
    return true;
  }
  return false;
}

}  // namespace

void WithdrawTiedCellSets(const DiagnosisOptions& options, DiagnosisState* st,
                          DiagnosisReport* report) {
  // Findings are adopted one per round, in order.
  std::vector<int> rounds(report->findings.size());
  for (size_t i = 0; i < rounds.size(); ++i) rounds[i] = static_cast<int>(i);
  for (bool by_type : {true, false}) {
    WithdrawIfTied(options, by_type, st, report, &rounds);
  }
  // The cells the model holds after the rounds, and their twins, taken
  // once: a withdrawn cell does not become a sibling of the next.
  const std::vector<TermScope> held =
      WithTwins(st->td, st->train, ModelCells(st->current.terms));
  while (WithdrawUnconfinedCell(options, held, st, report, &rounds)) {
  }
}

}  // namespace rollwear::diag
