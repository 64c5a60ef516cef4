// The factor cells the diagnosis offers (core/diagnosis/diagnosis_scoped.cc):
// one description per set of training readings, and the complement of a
// set of stand cells in a two-stand mill (ComplementCells).
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/fit/term_fit.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

std::vector<int> All(const TermData& td) {
  std::vector<int> all(td.obs.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return all;
}

std::vector<TermScope> OfferedCells(const TermData& td,
                                    const std::vector<int>& train) {
  std::vector<TermScope> cells;
  for (const diag::Candidate& c :
       diag::MakeCandidates(td, train, {}, DiagnosisOptions{})) {
    if (c.spec.term.form == TermForm::kCell) cells.push_back(c.spec.term.scope);
  }
  return cells;
}

// A roll type mounted on top rolls only: its stand cell (F7) and its
// roll-position cell (F7/top) cover the same readings, one description.
// Before session 17 both were offered (and counted in the Bonferroni
// factor). Every offered roll-type cell must hold a set of readings of its
// own; grade cells act on their grade's passes, so two grades' cells over
// the same readings are two descriptions and both stay: each grade's
// stand cells are offered (all grades roll at both stands here).
TEST(DiagnosisCellsTest, CellsOverTheSameReadingsAreOfferedOnce) {
  Simulation sim = simulator_test::Simulated(73, 120, {});
  Dataset& d = sim.data;
  const std::string moved = "ICDP-S1";
  const int x = static_cast<int>(
      std::find(d.roll_types.begin(), d.roll_types.end(), moved) -
      d.roll_types.begin());
  const int y = static_cast<int>(
      std::find(d.roll_types.begin(), d.roll_types.end(), "ICDP-S2") -
      d.roll_types.begin());
  ASSERT_LT(x, static_cast<int>(d.roll_types.size()));
  ASSERT_LT(y, static_cast<int>(d.roll_types.size()));
  for (Mount& m : d.mounts) {
    if (m.roll_type == x && m.position == Position::kBottom) m.roll_type = y;
  }
  StatusOr<TermData> td = BuildTermData(d, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  const std::vector<int> train = All(*td);
  std::set<std::vector<int>> seen;
  int of_moved = 0;
  std::set<std::string> graded;
  for (const TermScope& c : OfferedCells(*td, train)) {
    if (!c.grade.empty()) {
      if (c.stand > 0 && c.position < 0) graded.insert(c.grade);
      continue;
    }
    std::vector<int> inside;
    for (int o : train) {
      if (diag::InScope(*td, td->obs[o], c)) inside.push_back(o);
    }
    EXPECT_TRUE(seen.insert(inside).second) << c.Label();
    if (c.roll_type == moved) ++of_moved;
  }
  // ICDP-S1 runs at both stands, top only: one cell for the pair of places
  // (the twin rule keeps one of F6 and F7), not one per kind of place.
  EXPECT_EQ(of_moved, 1);
  // A grade's two stand cells are twins (one offered); a grade with too
  // few readings has none. (Here the frequent grades' reading sets differ,
  // so this checks that grade cells are offered, not that two grades over
  // the same readings both stay.)
  int frequent = 0;
  for (const std::string& g : d.grades) {
    const TermScope at_f7{7, -1, "", g};
    int n = 0;
    for (int o : train) n += diag::InScope(*td, td->obs[o], at_f7) ? 1 : 0;
    if (n >= 40 && n < static_cast<int>(train.size()) / 2) {
      ++frequent;
      EXPECT_EQ(graded.count(g), 1u) << g;
    }
  }
  EXPECT_GE(frequent, 2);
}

// In the simulator's two-stand mill four roll types run at both stands:
// the complement of two of them at F7 is the other two at F6, of one of
// them the other three; a set mixing stands has none.
TEST(DiagnosisCellsTest, TheComplementOfStandCellsIsTheOtherSharedLevels) {
  const Simulation sim = simulator_test::Simulated(74, 120, {});
  StatusOr<TermData> td = BuildTermData(sim.data, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  const std::vector<int> train = All(*td);
  const TermScope a{7, -1, "ICDP-S1", ""}, b{7, -1, "HSS-S2", ""};
  std::vector<TermScope> complement;
  ASSERT_TRUE(diag::ComplementCells(*td, train, DiagnosisThresholds{}, {a, b},
                                    &complement));
  std::set<std::string> types;
  for (const TermScope& c : complement) {
    EXPECT_EQ(c.stand, 6);
    EXPECT_EQ(c.position, -1);
    types.insert(c.roll_type);
  }
  EXPECT_EQ(types, (std::set<std::string>{"ICDP-S2", "HiCr-S2"}));
  ASSERT_TRUE(diag::ComplementCells(*td, train, DiagnosisThresholds{}, {a},
                                    &complement));
  EXPECT_EQ(complement.size(), 3u);
  const TermScope at_f6{6, -1, "HSS-S2", ""};
  EXPECT_FALSE(diag::ComplementCells(*td, train, DiagnosisThresholds{},
                                     {a, at_f6}, &complement));
  EXPECT_TRUE(complement.empty());
  const TermScope grade{7, -1, "", sim.data.grades.front()};
  EXPECT_FALSE(diag::ComplementCells(*td, train, DiagnosisThresholds{},
                                     {a, grade}, &complement));
}

}  // namespace
}  // namespace rollwear
