// Scoped and cell candidates of the diagnosis (diagnosis_internal.h): the
// vocabulary for effects that act on part of the mill only.
//
// Scoped variants: the simple one-parameter forms (log-linear, flag) of
// every wear-rate covariate restricted to one stand, one position (top or
// bottom), one roll position (a stand's top or bottom, "F7/top"), one roll
// type or one grade (TermScope, model_terms.h). The parameter count is
// that of the unscoped form; the scope is chosen by the same evidence as
// the form (score screen, LR, CV), and the Bonferroni count of the round
// (diagnosis_stages.cc, Screen::num_tests) includes every scoped variant, so
// the family-wise level stays alpha however many scopes there are.
//
// Cells: m = exp(b) on the passes of one (stand or roll position) x (roll
// type or grade) cell, the interactions the K structure (kF kR kS) cannot
// express, with the normal prior b ~ N(0, kCellPriorSd^2) (model_terms.h).
//
// A scope is offered only with at least min_scope_observations training
// measurements inside it, a cell with min_cell_observations
// (diagnosis_thresholds.h), and a scope covering every training observation
// is no scope.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/model/term_family.h"

namespace rollwear::diag {
namespace {

// Training observations inside `s`.
int CountInScope(const TermData& td, const std::vector<int>& train,
                 const TermScope& s) {
  int n = 0;
  for (int o : train) n += InScope(td, td.obs[o], s) ? 1 : 0;
  return n;
}

}  // namespace

bool InScope(const TermData& td, const TermObservation& ob,
             const TermScope& s) {
  const std::string rt = ob.roll_type >= 0 ? td.roll_types[ob.roll_type] : "";
  if (!s.CoversRoll(SlotStand(ob.slot), static_cast<int>(SlotPosition(ob.slot)),
                    rt)) {
    return false;
  }
  if (s.grade.empty() && s.gate.empty()) return true;
  const int grade = s.grade.empty()
                        ? -1
                        : static_cast<int>(std::find(td.grades.begin(),
                                                     td.grades.end(), s.grade) -
                                           td.grades.begin());
  const int gate = s.gate.empty() ? -1 : td.CovariateIndex(s.gate);
  if (!s.gate.empty() && gate < 0) return false;
  // Inside when one of its passes is of the grade and inside the gate.
  for (int i = ob.pass_begin; i < ob.pass_end; ++i) {
    if ((grade < 0 || td.grade[i] == grade) &&
        (gate < 0 || s.CoversGateValue(td.z[gate][i]))) {
      return true;
    }
  }
  return false;
}

std::vector<TermScope> SingleScopes(const TermData& td,
                                    const std::vector<int>& train,
                                    const DiagnosisThresholds& thresholds,
                                    bool keep_everywhere) {
  std::vector<TermScope> all;
  std::vector<bool> stands(kMaxStand + 1, false);
  for (const std::string& p : td.positions) {
    const int st = ParseStand(p.substr(0, p.find('/')));
    if (st > 0) stands[st] = true;
  }
  for (int st = kMinStand; st <= kMaxStand; ++st) {
    if (stands[st]) all.push_back({st, -1, "", ""});
  }
  all.push_back({0, static_cast<int>(Position::kTop), "", ""});
  all.push_back({0, static_cast<int>(Position::kBottom), "", ""});
  // One roll position ("F7/top"): the K structure's own place (kF).
  for (const std::string& p : td.positions) {
    const size_t slash = p.find('/');
    Position pos;
    const int st = ParseStand(p.substr(0, slash));
    if (st > 0 && slash != std::string::npos &&
        ParsePosition(p.substr(slash + 1), &pos)) {
      all.push_back({st, static_cast<int>(pos), "", ""});
    }
  }
  for (const std::string& r : td.roll_types) all.push_back({0, -1, r, ""});
  for (const std::string& g : td.grades) all.push_back({0, -1, "", g});
  std::vector<TermScope> out;
  const int n = static_cast<int>(train.size());
  for (const TermScope& s : all) {
    const int in = CountInScope(td, train, s);
    if (in >= thresholds.min_scope_observations &&
        (in < n || keep_everywhere)) {
      out.push_back(s);
    }
  }
  return out;
}

namespace {

// The (stand or position) x (roll type or grade) cells with enough data.
// When a roll type or grade runs in exactly two places of a kind (two
// stands, or top and bottom), the two cells describe the same data (the
// factor's own K level absorbs the rest: x1.3 at F7 = x1/1.3 at F6), so only
// the cell with fewer observations, the exception, is offered; and a cell
// holding all of the level's data (a roll type used at one stand only) is
// the level's own K coefficient, not a cell.
std::vector<TermScope> CellScopes(const TermData& td,
                                  const std::vector<int>& train,
                                  const DiagnosisThresholds& thresholds,
                                  const std::vector<TermScope>& single) {
  std::vector<TermScope> where_stand, where_pos, where_roll, what;
  for (const TermScope& s : single) {
    if (s.stand > 0 && s.position < 0) {
      where_stand.push_back(s);
    } else if (s.stand == 0 && s.position >= 0) {
      where_pos.push_back(s);
    } else if (s.stand > 0 && s.position >= 0) {
      where_roll.push_back(s);
    } else if (!s.roll_type.empty() || !s.grade.empty()) {
      what.push_back(s);
    }
  }
  std::vector<TermScope> out;
  for (const std::vector<TermScope>* where :
       {&where_stand, &where_pos, &where_roll}) {
    for (const TermScope& b : what) {
      std::vector<std::pair<int, TermScope>> cells;
      int total = 0;
      for (const TermScope& a : *where) {
        TermScope c = a;
        c.roll_type = b.roll_type;
        c.grade = b.grade;
        const int n = CountInScope(td, train, c);
        total += n;
        if (n >= thresholds.min_cell_observations) cells.emplace_back(n, c);
      }
      // A cell holding all of its factor level's data is that level's own K.
      if (cells.size() == 1 && cells[0].first == total) continue;
      if (cells.size() == 2 && cells[0].first + cells[1].first == total) {
        out.push_back(cells[0].first <= cells[1].first ? cells[0].second
                                                       : cells[1].second);
        continue;
      }
      for (const auto& [n, c] : cells) out.push_back(c);
    }
  }
  // Two roll-type cells over the same training readings are one
  // description (a roll type that runs on top rolls only: its stand cell
  // and its F7/top cell): the first, the wider place, is kept, and the
  // Bonferroni factor counts it once
  // (DiagnosisCellsTest.CellsOverTheSameReadingsAreOfferedOnce). Not grade
  // cells: a grade cell acts on its grade's passes, and two of them can hold
  // the same readings with different passes.
  std::set<std::vector<int>> seen;
  std::erase_if(out, [&](const TermScope& c) {
    if (!c.grade.empty()) return false;
    std::vector<int> inside;
    for (int o : train) {
      if (InScope(td, td.obs[o], c)) inside.push_back(o);
    }
    return !seen.insert(std::move(inside)).second;
  });
  return out;
}

}  // namespace

TermSpec CellTermSpec(const TermData& td, const TermScope& scope) {
  TermSpec t;
  t.covariate = td.CovariateIndex(kCellCovariateName);
  t.term.covariate = kCellCovariateName;
  t.term.form = TermForm::kCell;
  t.term.params = {0.0};
  t.term.scope = scope;
  t.lower = {-3.0};
  t.upper = {3.0};
  t.prior_sd = kCellPriorSd;
  return t;
}

bool SameCellKind(const TermScope& a, const TermScope& b) {
  return (a.stand > 0) == (b.stand > 0) &&
         (a.position >= 0) == (b.position >= 0) &&
         a.roll_type.empty() == b.roll_type.empty();
}

std::vector<TermScope> WithTwins(const TermData& td,
                                 const std::vector<int>& train,
                                 const DiagnosisThresholds& thresholds,
                                 const std::vector<TermScope>& cells) {
  std::vector<TermScope> out = cells;
  for (const TermScope& c : cells) {
    TermScope twin;
    if (TwinCell(td, train, thresholds, c, &twin)) out.push_back(twin);
  }
  return out;
}

std::vector<TermScope> ModelCells(const std::vector<TermSpec>& terms) {
  std::vector<TermScope> out;
  for (const TermSpec& t : terms) {
    if (t.term.form == TermForm::kCell) out.push_back(t.term.scope);
  }
  return out;
}

std::vector<TermScope> OfferedCellScopes(
    const TermData& td, const std::vector<int>& train,
    const DiagnosisThresholds& thresholds) {
  return CellScopes(td, train, thresholds, SingleScopes(td, train, thresholds));
}

bool TwinCell(const TermData& td, const std::vector<int>& train,
              const DiagnosisThresholds& thresholds, const TermScope& cell,
              TermScope* twin) {
  if (cell.roll_type.empty() == cell.grade.empty()) return false;
  std::vector<TermScope> places;
  if (cell.stand > 0) {
    // A stand's cells, or a roll position's (F7/bottom): its places are the
    // other scopes of the same kind.
    const bool roll_position = cell.position >= 0;
    for (const TermScope& s : SingleScopes(td, train, thresholds)) {
      if (s.stand > 0 && (s.position >= 0) == roll_position)
        places.push_back(s);
    }
  } else if (cell.position >= 0) {
    places.push_back({0, static_cast<int>(Position::kTop), "", ""});
    places.push_back({0, static_cast<int>(Position::kBottom), "", ""});
  } else {
    return false;
  }
  std::vector<TermScope> with_data;
  for (TermScope c : places) {
    c.roll_type = cell.roll_type;
    c.grade = cell.grade;
    if (CountInScope(td, train, c) > 0) with_data.push_back(c);
  }
  if (with_data.size() != 2) return false;
  if (with_data[0] == cell) {
    *twin = with_data[1];
  } else if (with_data[1] == cell) {
    *twin = with_data[0];
  } else {
    return false;
  }
  return true;
}

bool ComplementCells(const TermData& td, const std::vector<int>& train,
                     const DiagnosisThresholds& thresholds,
                     const std::vector<TermScope>& cells,
                     std::vector<TermScope>* complement) {
  complement->clear();
  if (cells.empty()) return false;
  const TermScope& first = cells.front();
  const bool by_type = !first.roll_type.empty();
  for (const TermScope& c : cells) {
    if (c.stand != first.stand || c.stand <= 0 || c.position >= 0 ||
        c.roll_type.empty() == by_type || c.grade.empty() != by_type) {
      return false;
    }
  }
  std::vector<int> stands;
  for (const TermScope& s : SingleScopes(td, train, thresholds, true)) {
    if (s.stand > 0 && s.position < 0) stands.push_back(s.stand);
  }
  if (stands.size() != 2 ||
      std::find(stands.begin(), stands.end(), first.stand) == stands.end()) {
    return false;
  }
  const int other = stands[0] == first.stand ? stands[1] : stands[0];
  for (const std::string& level : by_type ? td.roll_types : td.grades) {
    const bool named =
        std::any_of(cells.begin(), cells.end(), [&](const TermScope& c) {
          return (by_type ? c.roll_type : c.grade) == level;
        });
    if (named) continue;
    TermScope here{first.stand, -1, by_type ? level : "", by_type ? "" : level};
    TermScope there = here;
    there.stand = other;
    if (CountInScope(td, train, here) > 0 &&
        CountInScope(td, train, there) > 0) {
      complement->push_back(there);
    }
  }
  return true;
}

void AddScopedCandidates(const TermData& td, const std::vector<int>& train,
                         const DiagnosisThresholds& thresholds,
                         const std::set<int>& used,
                         const std::vector<TermScope>& adopted_cells,
                         std::vector<Candidate>* out) {
  const std::vector<TermScope> scopes = SingleScopes(td, train, thresholds);
  // Scoped variants of the unscoped candidates whose family is offered
  // scoped (term_family.h: the one-parameter wear families).
  const size_t unscoped = out->size();
  for (size_t i = 0; i < unscoped; ++i) {
    const TermSpec s = (*out)[i].spec;  // a copy: push_back reallocates
    if (!FamilyOf(s.term.form).offered_scoped()) continue;
    if (td.catalog[s.covariate].locate_only) continue;  // a rival, never named
    for (const TermScope& scope : scopes) {
      Candidate c{s, {}};
      c.spec.term.scope = scope;
      out->push_back(std::move(c));
    }
    if (!FamilyOf(s.term.form).offered_gated()) continue;
    for (const TermScope& scope :
         GateScopes(td, train, thresholds, s.covariate)) {
      Candidate c{s, {}};
      c.spec.term.scope = scope;
      out->push_back(std::move(c));
    }
  }
  const int cell = td.CovariateIndex(kCellCovariateName);
  if (cell < 0 || used.count(cell) > 0) return;
  // Cells already in the model (and their twins, which describe the same
  // data) are not offered again; every other cell is: a mill can have two
  // factor combinations the K structure cannot express, and a round
  // without the cell to compare with names a covariate stand-in for it.
  const std::vector<TermScope> taken =
      WithTwins(td, train, thresholds, adopted_cells);
  const auto adopted = [&](const TermScope& scope) {
    return std::find(taken.begin(), taken.end(), scope) != taken.end();
  };
  for (const TermScope& scope : CellScopes(td, train, thresholds, scopes)) {
    if (adopted(scope)) continue;
    Candidate c;
    c.spec = CellTermSpec(td, scope);
    out->push_back(std::move(c));
  }
}

}  // namespace rollwear::diag
