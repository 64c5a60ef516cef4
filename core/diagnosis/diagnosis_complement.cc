// A set of adopted stand cells that the data cannot tell from its
// complement (docs/diagnosis.md, "Cell sets at two stands"). In a mill
// measured at two stands s and t, with K by roll position, roll type and
// grade (option 1), the cells of one factor form a two-row table whose
// interaction is identified only up to a constant: roll types A and B
// wearing x m more at s predict every reading exactly as the factor's other
// types that run at both stands wearing x m more at t (ComplementCells). The
// data then prefer the sparser description, and when the complement has no
// more cells than the named set (two of four roll types at F7 read exactly
// as the other two at F6) neither is identified
// (DiagnosisProxyTest.TwoRollTypesAtOneStandAreLocatedWithTheirEquivalentPair).
// The set is withdrawn: its findings become runners-up, its terms leave the
// model (refitted without them), and the mismatch is listed as located,
// `stand_by_roll_type` or `stand_by_grade`, naming both descriptions.
// A set whose complement has more cells (one roll type of four at F7, one
// grade of ten) stays named: it is the sparsest description, unless
// other cells of its kind join one of its cells significantly in the final
// model, or two of them describe the data about as well as it does
// (WithdrawUnconfinedCell): then the set the rounds adopted is incomplete,
// or not identified, and that cell is withdrawn and located with them.
// Thread-safety: reentrant (changes only its arguments).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
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

// `terms` without the cell terms whose scope is one of `cells`.
std::vector<TermSpec> TermsWithoutCells(const std::vector<TermSpec>& terms,
                                        const std::vector<TermScope>& cells) {
  std::vector<TermSpec> kept;
  for (const TermSpec& t : terms) {
    const bool dropped =
        t.term.form == TermForm::kCell &&
        std::find(cells.begin(), cells.end(), t.term.scope) != cells.end();
    if (!dropped) kept.push_back(t);
  }
  return kept;
}

// The current model without `cells`, refitted with its own noise sd.
Fitted RefitWithoutCells(const DiagnosisOptions& options,
                         const DiagnosisState& st,
                         const std::vector<TermScope>& cells) {
  return FitWithOwnNoise(st, options, st.current.log_k,
                         TermsWithoutCells(st.current.terms, cells));
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
  if (!ComplementCells(st->td, st->train, options.thresholds, cells,
                       &complement) ||
      complement.size() > cells.size()) {
    return false;
  }
  const Fitted refit = RefitWithoutCells(options, *st, cells);
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
                                  f.p_adjusted, f.cv_mse_ratio, reason,
                                  RefusalKind::kTwinStands, ""});
  }
  for (auto it = index.rbegin(); it != index.rend(); ++it) {
    report->findings.erase(report->findings.begin() + *it);
    rounds->erase(rounds->begin() + *it);
  }
  report->unexplained.push_back(u);
  st->current = refit;
  return true;
}

bool SamePlace(const TermScope& a, const TermScope& b) {
  return a.stand == b.stand && a.position == b.position;
}

// Cell `s` at `place` (*there = s), or its twin there (TwinCell: the same
// description of the data when its level runs at two places); false when
// neither is.
bool AtPlace(const DiagnosisState& st, const TermScope& s,
             const TermScope& place, TermScope* there) {
  if (SamePlace(s, place)) {
    *there = s;
    return true;
  }
  TermScope twin;
  if (TwinCell(st.td, st.train, st.thresholds, s, &twin) &&
      SamePlace(twin, place)) {
    *there = twin;
    return true;
  }
  return false;
}

// The other offered cells of `cell`'s kind at its place or its twin's
// place, not `held`.
std::vector<TermScope> SiblingCells(const DiagnosisState& st,
                                    const TermScope& cell,
                                    const std::vector<TermScope>& held) {
  TermScope twin = cell;
  TwinCell(st.td, st.train, st.thresholds, cell, &twin);
  std::vector<TermScope> out;
  for (const TermScope& c : OfferedCellScopes(st.td, st.train, st.thresholds)) {
    if (SameCellKind(c, cell) && (SamePlace(c, cell) || SamePlace(c, twin)) &&
        std::find(held.begin(), held.end(), c) == held.end()) {
      out.push_back(c);
    }
  }
  return out;
}

// The levels of `cell`'s kind (its grade or roll type) that the training
// readings at its place (stand, or roll position) hold.
std::set<std::string> LevelsAtPlace(const DiagnosisState& st,
                                    const TermScope& cell) {
  std::set<std::string> out;
  const TermScope place{cell.stand, cell.position, "", ""};
  for (int o : st.train) {
    const TermObservation& ob = st.td.obs[o];
    if (!InScope(st.td, ob, place)) continue;
    if (!cell.roll_type.empty()) {
      if (ob.roll_type >= 0) out.insert(st.td.roll_types[ob.roll_type]);
      continue;
    }
    for (int i = ob.pass_begin; i < ob.pass_end; ++i) {
      out.insert(st.td.grades[st.td.grade[i]]);
    }
  }
  return out;
}

// One free cell per other level: each sibling at `cell`'s place, or its
// twin there (the same description of the data when the level runs at two
// places: its own K takes up the rest), else as offered. Sets *df to the
// free parameters they add: one fewer when they and `cell` cover every
// level at the place (their product is the place's own K).
std::vector<TermScope> AllSiblingsAtPlace(const DiagnosisState& st,
                                          const TermScope& cell,
                                          const std::vector<TermScope>& sibs,
                                          int* df) {
  std::vector<TermScope> out;
  std::set<std::string> covered = {cell.roll_type + cell.grade};
  for (const TermScope& s : sibs) {
    TermScope t = s;
    AtPlace(st, s, cell, &t);
    const std::string level = t.roll_type + t.grade;
    if (SamePlace(t, cell) && !covered.insert(level).second) continue;
    if (std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
  }
  bool all = true;
  for (const std::string& level : LevelsAtPlace(st, cell)) {
    all = all && covered.count(level) > 0;
  }
  *df = static_cast<int>(out.size()) - (all ? 1 : 0);
  return out;
}

// How the other offered cells of a cell's kind join it in the final model:
// the strongest one alone (nested LR ~ chi2(1), Wilks 1938; Bonferroni over
// the siblings) and all of them at once (one per level, LR ~ chi2(df)),
// each at half the level (Bonferroni over the two tests). The omnibus test
// finds a set whose other members are each too weak to pass the
// single-sibling test: two grades wearing F7 more can each fall short of
// it (the strongest of eight siblings LR 8.8, p 0.003 before Bonferroni)
// while all of them at once clear it (7 free cells, LR 26.2, p 0.0005)
// (DiagnosisInsideCellTest.ACellIsWithdrawnWhenItsSetWasAdoptedInPart).
struct Joining {
  const TermScope* strongest = nullptr;  // the strongest single sibling
  double lr = 0, p = 1, p_adjusted = 1;  // of the test reported
  int df = 1;                            // 1: the single test
};
Joining SiblingsJoin(const DiagnosisState& st, const std::vector<double>& sd,
                     const Fitted& base, const TermScope& cell,
                     const std::vector<TermScope>& siblings) {
  std::vector<TermSpec> cells;
  for (const TermScope& s : siblings) cells.push_back(CellTermSpec(st.td, s));
  const StrongestAlternative a = Strongest(st, sd, base, cells);
  Joining j;
  if (a.index < 0) return j;
  j.strongest = &siblings[a.index];
  j.lr = a.test.lr;
  j.p = a.test.p;
  // Any of the siblings, or all at once, joining withdraws the cell: two
  // tests, the first over the siblings.
  j.p_adjusted =
      AnyOf(st.thresholds, 2.0 * static_cast<double>(siblings.size()))
          .Adjusted(a.test.p);
  int df = 0;
  const std::vector<TermScope> all =
      AllSiblingsAtPlace(st, cell, siblings, &df);
  if (df < 2) return j;
  std::vector<TermSpec> terms = base.terms;
  for (const TermScope& s : all) terms.push_back(CellTermSpec(st.td, s));
  const Encompassing together =
      Encompassed(st, base, Fit(st.td, st.train, sd, base.log_k, terms), df);
  if (!together.usable()) return j;
  const double p_adjusted = AnyOf(st.thresholds, 2).Adjusted(together.p);
  if (p_adjusted < j.p_adjusted) {
    j.lr = together.lr;
    j.p = together.p;
    j.p_adjusted = p_adjusted;
    j.df = df;
  }
  return j;
}

// The pairs of `siblings` that restate `cell`: the pair that with the cell
// covers every level at the cell's place is the cell restated (the place's
// own K takes up the common factor, the pair at the cell's inverse
// multiplier), and so is the pair that covers the rest at its twin's place
// (TwinCell: the same data), each sibling taken at the place or as its
// twin there (as in AllSiblingsAtPlace): one description with a cell more,
// not a rival (the sparser one is named, as for the complement at the
// other stand, ComplementCells).
class CellRestatements {
 public:
  CellRestatements(const DiagnosisState& st, const TermScope& cell,
                   const std::vector<TermScope>& siblings) {
    std::vector<TermScope> places = {cell};
    TermScope twin;
    if (TwinCell(st.td, st.train, st.thresholds, cell, &twin))
      places.push_back(twin);
    for (const TermScope& place : places) {
      Place p;
      p.own = place.roll_type + place.grade;
      p.levels = LevelsAtPlace(st, place);
      for (const TermScope& s : siblings) {
        TermScope there;
        p.level.push_back(
            AtPlace(st, s, place, &there) ? there.roll_type + there.grade : "");
      }
      places_.push_back(std::move(p));
    }
  }

  // Whether siblings a and b (indices) restate the cell.
  bool ByPair(size_t a, size_t b) const {
    for (const Place& p : places_) {
      if (p.level[a].empty() || p.level[b].empty()) continue;
      const std::set<std::string> covered = {p.own, p.level[a], p.level[b]};
      if (std::includes(covered.begin(), covered.end(), p.levels.begin(),
                        p.levels.end())) {
        return true;
      }
    }
    return false;
  }

 private:
  struct Place {
    std::string own;                 // the cell's (or twin's) level
    std::set<std::string> levels;    // LevelsAtPlace
    std::vector<std::string> level;  // each sibling's level there, or ""
  };
  std::vector<Place> places_;
};

// Two other cells that describe the data about as well as one adopted
// cell: the pair's and the cell's LR against the model without the cell.
struct RivalPair {
  std::string label;  // "F6, grade DQ and F6, grade S355"; empty: none
  double lr_pair = 0, lr_cell = 0;
};

// The best pair of `siblings` in place of `cell` in `base` (fitted with
// the noise sd `sd`); label empty when no pair comes within
// thresholds.rival_pair_margin (diagnosis_thresholds.h) of the cell. The
// pair that is the cell's complement at its place or its twin's (each
// sibling taken there or as its twin there) is not tried.
RivalPair BestRivalPair(const DiagnosisState& st, const std::vector<double>& sd,
                        const Fitted& base, const TermScope& cell,
                        const std::vector<TermScope>& siblings) {
  RivalPair r;
  const std::vector<TermSpec> without = TermsWithoutCells(base.terms, {cell});
  const Fitted b0 = Fit(st.td, st.train, sd, base.log_k, without);
  if (!b0.usable || !(b0.rss > 0)) return r;
  const double n = static_cast<double>(st.train.size());
  r.lr_cell = NestedLr(n, b0.rss, base.rss);
  double best = -1;
  std::string label;
  const CellRestatements restated(st, cell, siblings);
  for (size_t a = 0; a < siblings.size(); ++a) {
    for (size_t b = a + 1; b < siblings.size(); ++b) {
      if (restated.ByPair(a, b)) continue;
      std::vector<TermSpec> terms = without;
      terms.push_back(CellTermSpec(st.td, siblings[a]));
      terms.push_back(CellTermSpec(st.td, siblings[b]));
      const Fitted pair = Fit(st.td, st.train, sd, base.log_k, terms);
      if (!pair.usable || !(pair.rss > 0)) continue;
      const double lr = NestedLr(n, b0.rss, pair.rss);
      if (lr > best) {
        best = lr;
        label = siblings[a].Label() + " and " + siblings[b].Label();
      }
    }
  }
  if (best >= r.lr_cell - st.thresholds.rival_pair_margin) {
    r.label = label;
    r.lr_pair = best;
  }
  return r;
}

// Withdraws the first adopted cell that is not confined (the other cells
// of its kind at its place, or its twin's, added to the final model, join
// it significantly: SiblingsJoin, at alternative_alpha) or not
// identified (two of them in its place describe the data about as well:
// BestRivalPair). Either way the effect lives in a set of cells the rounds
// did not name, and the named cell would say "elsewhere the law holds" of
// the rest (two grades wearing one stand more, named as one of them or as
// a third grade at the other stand:
// DiagnosisInsideCellTest.ACellIsWithdrawnWhenItsSetWasAdoptedInPart).
// True when it withdrew one. After the
// rounds, so that two true cells both adopted are not refused for each
// other.
bool WithdrawUnconfinedCell(const DiagnosisOptions& options,
                            const std::vector<TermScope>& held,
                            DiagnosisState* st, DiagnosisReport* report,
                            std::vector<int>* rounds) {
  std::vector<double> sd;
  const Fitted base =
      FitWithOwnNoise(*st, options, st->current.log_k, st->current.terms, &sd);
  if (!base.usable || !(base.rss > 0)) return false;
  const double alpha = options.thresholds.alternative_alpha;
  for (size_t i = 0; i < report->findings.size(); ++i) {
    const Finding& f = report->findings[i];
    const TermScope cell = f.term.scope;
    if (f.term.form != TermForm::kCell) continue;
    const std::vector<TermScope> siblings = SiblingCells(*st, cell, held);
    const Joining j = SiblingsJoin(*st, sd, base, cell, siblings);
    const bool joined = j.strongest != nullptr && j.p_adjusted < alpha;
    const RivalPair rival =
        joined ? RivalPair{} : BestRivalPair(*st, sd, base, cell, siblings);
    if (!joined && rival.label.empty()) continue;
    const Fitted refit = RefitWithoutCells(options, *st, {cell});
    if (!refit.usable) return false;
    const std::string kind = cell.roll_type.empty() ? "grades" : "roll types";
    char buf[480];
    Unexplained u;
    u.dimension =
        std::string(cell.position >= 0 ? "position_by_" : "stand_by_") +
        (cell.roll_type.empty() ? "grade" : "roll_type");
    u.test = "likelihood_ratio";
    if (joined) {
      const std::string joiners =
          j.df == 1
              ? "the cell " + j.strongest->Label()
              : "the other " + kind + " there (" + std::to_string(j.df) +
                    " free cells; the strongest " + j.strongest->Label() + ")";
      std::snprintf(buf, sizeof(buf),
                    "withdrawn: not confined to %s: %s join%s it "
                    "significantly (LR %.1f, p adjusted %.2g); a set of cells "
                    "of which one named alone would say the rest follow the "
                    "law",
                    cell.Label().c_str(), joiners.c_str(), j.df == 1 ? "s" : "",
                    j.lr, j.p_adjusted);
      u.where = cell.Label() + " and " +
                (j.df == 1 ? j.strongest->Label()
                           : "the other " + kind + " there, the strongest " +
                                 j.strongest->Label());
      u.statistic = j.lr;
      u.p_value = j.p;
      u.p_adjusted = j.p_adjusted;
    } else {
      std::snprintf(buf, sizeof(buf),
                    "withdrawn: %s describe the data about as well as %s "
                    "(LR %.1f against %.1f, with one cell more); the data do "
                    "not say which cells wear differently",
                    rival.label.c_str(), cell.Label().c_str(), rival.lr_pair,
                    rival.lr_cell);
      u.where = cell.Label() + ", or as well " + rival.label;
      u.statistic = rival.lr_cell;
      u.p_value = f.p_value;
      u.p_adjusted = f.p_adjusted;
    }
    u.mean_residual_um = ContributionRmsUm(*st, st->current, refit, {cell});
    WithdrawFinding(i, buf, RefusalKind::kCellPair, "", u, refit, st, report,
                    rounds);
    return true;
  }
  return false;
}

}  // namespace

void WithdrawFinding(size_t i, const std::string& reason, RefusalKind kind,
                     const std::string& guard, const Unexplained& located,
                     const Fitted& refit, DiagnosisState* st,
                     DiagnosisReport* report, std::vector<int>* rounds) {
  const Finding& f = report->findings[i];
  report->runners_up.push_back({(*rounds)[i], f.covariate, f.form, f.p_adjusted,
                                f.cv_mse_ratio, reason, kind, guard});
  report->unexplained.push_back(located);
  report->findings.erase(report->findings.begin() + i);
  rounds->erase(rounds->begin() + i);
  st->current = refit;
}

std::vector<int> WithdrawTiedCellSets(const DiagnosisOptions& options,
                                      DiagnosisState* st,
                                      DiagnosisReport* report) {
  // Findings are adopted one per round, in order.
  std::vector<int> rounds(report->findings.size());
  for (size_t i = 0; i < rounds.size(); ++i) rounds[i] = static_cast<int>(i);
  for (bool by_type : {true, false}) {
    WithdrawIfTied(options, by_type, st, report, &rounds);
  }
  // The cells the model holds after the rounds, and their twins, taken
  // once: a withdrawn cell does not become a sibling of the next.
  const std::vector<TermScope> held = WithTwins(
      st->td, st->train, options.thresholds, ModelCells(st->current.terms));
  while (WithdrawUnconfinedCell(options, held, st, report, &rounds)) {
  }
  return rounds;
}

}  // namespace rollwear::diag
