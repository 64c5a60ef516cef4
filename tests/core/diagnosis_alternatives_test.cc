// Alternatives to a winner (diagnosis_alternatives.h): the one multiplicity
// policy (any of k: Bonferroni; each of k: unadjusted; a re-test of the
// winner: the round's family) and the encompassing test, which among the
// cells the candidates offer picks the one a roll type's extra wear at one
// stand lives in, and on a clean mill finds none that adds.
#include "core/diagnosis/diagnosis_alternatives.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
// A named namespace: the tests are compiled in unity batches.
namespace alternatives_test {
namespace {

constexpr int kCampaigns = test_size::FullOr(250, 150);

TEST(DiagnosisAlternativesTest, AnyOfIsBonferroniEachOfIsEachTestsLevel) {
  DiagnosisOptions options;
  const DiagnosisThresholds& t = options.thresholds;
  ASSERT_DOUBLE_EQ(t.alternative_alpha, 0.01);
  // Any of four: family-wise 1 %, each at 0.25 %.
  const diag::Multiplicity any = diag::AnyOf(t, 4);
  EXPECT_DOUBLE_EQ(any.Adjusted(0.002), 0.008);
  EXPECT_TRUE(any.Rejects(0.002));
  EXPECT_FALSE(any.Rejects(0.003));  // 0.012 adjusted
  EXPECT_DOUBLE_EQ(any.Adjusted(0.5), 1.0);
  // No alternative counts as one look, never as zero.
  EXPECT_DOUBLE_EQ(diag::AnyOf(t, 0).looks, 1.0);
  // Each of k: every test at 1 %, whatever k.
  const diag::Multiplicity each = diag::EachOf(t);
  EXPECT_TRUE(each.Rejects(0.009));
  EXPECT_FALSE(each.Rejects(0.011));
  // The winner's own effect again: the round's alpha over its tests.
  const diag::Multiplicity round = diag::RoundFamily(options, 50);
  EXPECT_TRUE(round.Rejects(1.9e-5));   // 9.5e-4 < 1e-3
  EXPECT_FALSE(round.Rejects(2.1e-5));  // 1.05e-3
  EXPECT_DOUBLE_EQ(round.Adjusted(1e-5), 5e-4);
}

// The baseline state of a simulated mill and its model's noise sd.
struct Prepared {
  diag::DiagnosisState st;
  std::vector<double> sd;
  diag::Fitted base;
};
Prepared Prepare(uint64_t seed, std::vector<std::string> effects) {
  Prepared p;
  const Simulation sim =
      simulator_test::Simulated(seed, kCampaigns, std::move(effects));
  const DiagnosisOptions options;
  DiagnosisReport report;
  StatusOr<diag::Baseline> base = diag::RunBaseline(sim.data, options, &report);
  EXPECT_TRUE(base.ok()) << base.status().ToString();
  if (!base.ok()) return p;
  StatusOr<diag::DiagnosisState> st =
      diag::BuildState(sim.data, options, *base, &report);
  EXPECT_TRUE(st.ok()) << st.status().ToString();
  if (!st.ok()) return p;
  p.st = std::move(st).value();
  p.base = diag::FitWithOwnNoise(p.st, options, p.st.current.log_k,
                                 p.st.current.terms, &p.sd);
  return p;
}

std::vector<TermSpec> OfferedCells(const diag::DiagnosisState& st) {
  std::vector<TermSpec> out;
  for (const TermScope& s :
       diag::OfferedCellScopes(st.td, st.train, st.thresholds)) {
    out.push_back(diag::CellTermSpec(st.td, s));
  }
  return out;
}

TEST(DiagnosisAlternativesTest, TheStrongestCellIsWhereTheRollTypeWearsMore) {
  // roll_type_stand:2: HiCr-S2 wears x1.2..1.5 at F7 only (it runs at F6
  // and F7, so its F6 cell is the twin).
  const Prepared p = Prepare(101, {"roll_type_stand:2"});
  ASSERT_TRUE(p.base.usable);
  const std::vector<TermSpec> cells = OfferedCells(p.st);
  ASSERT_GE(cells.size(), 10u);
  const diag::StrongestAlternative s =
      diag::Strongest(p.st, p.sd, p.base, cells);
  ASSERT_GE(s.index, 0);
  const TermScope& where = cells[s.index].term.scope;
  EXPECT_EQ(where.roll_type, "HiCr-S2") << where.Label();
  EXPECT_TRUE(where.stand == 7 || where.stand == 6) << where.Label();
  EXPECT_EQ(s.test.df, 1);
  EXPECT_TRUE(diag::AnyOf(p.st.thresholds, static_cast<double>(cells.size()))
                  .Rejects(s.test.p))
      << "LR " << s.test.lr << " p " << s.test.p;
  EXPECT_GT(s.test.lr, 30) << where.Label();
  // The strongest is the smallest p of the cells' tests one by one, and
  // not merely the first cell offered.
  int argmin = -1;
  double p_min = 1;
  for (size_t i = 0; i < cells.size(); ++i) {
    const diag::Encompassing e = diag::Encompass(p.st, p.sd, p.base, cells[i]);
    if (e.usable() && e.p < p_min) {
      p_min = e.p;
      argmin = static_cast<int>(i);
    }
  }
  EXPECT_EQ(s.index, argmin);
  EXPECT_GT(s.index, 0) << "the test needs a strongest cell that is not the "
                           "first offered";
  // The statistic is the nested likelihood ratio of the two fits.
  EXPECT_NEAR(s.test.lr,
              static_cast<double>(p.st.train.size()) *
                  std::log(p.base.rss / s.test.with.rss),
              1e-9 * s.test.lr);
  // A fit that failed is no evidence: LR 0, p 1.
  const diag::Encompassing failed =
      diag::Encompassed(p.st, p.base, diag::Fitted{}, 1);
  EXPECT_FALSE(failed.usable());
  EXPECT_EQ(failed.lr, 0);
  EXPECT_EQ(failed.p, 1);
}

TEST(DiagnosisAlternativesTest, OnACleanMillNoCellAdds) {
  for (uint64_t seed : {101u, 102u}) {
    const Prepared p = Prepare(seed, {});
    ASSERT_TRUE(p.base.usable);
    const std::vector<TermSpec> cells = OfferedCells(p.st);
    const diag::StrongestAlternative s =
        diag::Strongest(p.st, p.sd, p.base, cells);
    if (s.index < 0) continue;  // none adds at all
    EXPECT_FALSE(diag::AnyOf(p.st.thresholds, static_cast<double>(cells.size()))
                     .Rejects(s.test.p))
        << "seed " << seed << ": " << cells[s.index].term.scope.Label()
        << " LR " << s.test.lr << " p " << s.test.p;
  }
}

}  // namespace
}  // namespace alternatives_test
}  // namespace rollwear
