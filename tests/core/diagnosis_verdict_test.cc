// The third verdict: a mismatch the vocabulary cannot express must be
// located and reported as `mismatch_located_unexplained`, with where it
// lives and no physics named; clean data must stay
// `no_significant_mismatch` with nothing unexplained. The inexpressible
// effects are written into a clean simulation's measured wear directly:
// an alternating offset (+-10 µm) between consecutive campaigns, a square wave over
// calendar time with a period of 16 campaigns, and extra grinder noise on
// one roll position only.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/random.h"
#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

// Reduced under the sanitizers (test_size.h); the effects are sized so
// that the assertions hold at both sizes.
constexpr int kCampaigns = test_size::FullOr(395, 200);
// The paper's size, also under the sanitizers, for the cases whose
// evidence is too weak at 200 campaigns (session-9 ASan run: the square
// wave and the grade cell went unlocated, the roll-type cell was named as
// `reduction`; docs/diagnosis.md, Limits).

Dataset Clean(uint64_t seed, int campaigns = kCampaigns) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  StatusOr<Simulation> s = Simulate(o);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return std::move(s).value().data;
}

// Campaign index -> rank in calendar time (started_at).
std::vector<int> TimeRank(const Dataset& d) {
  std::vector<int> order(d.campaigns.size()), rank(d.campaigns.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return d.campaigns[a].started_at < d.campaigns[b].started_at;
  });
  for (size_t r = 0; r < order.size(); ++r)
    rank[order[r]] = static_cast<int>(r);
  return rank;
}

using simulator_test::DescribeReport;

bool Lists(const DiagnosisReport& r, const std::string& dimension_prefix,
           const std::string& where_part = "") {
  for (const Unexplained& u : r.unexplained) {
    if (u.dimension.rfind(dimension_prefix, 0) == 0 &&
        u.where.find(where_part) != std::string::npos) {
      EXPECT_LT(u.p_adjusted, DiagnosisOptions{}.alpha);
      return true;
    }
  }
  return false;
}

DiagnosisReport Diagnosed(const Dataset& d) {
  StatusOr<DiagnosisReport> r = Diagnose(d, DiagnosisOptions{});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  if (!r.ok()) return DiagnosisReport{};
  std::printf("%s\n", DescribeReport(*r).c_str());
  return std::move(r).value();
}

// The verdict on `d` is mismatch_located_unexplained, nothing is named,
// and `unexplained` lists a check of one of `dimensions` at `where_part`.
void ExpectLocatedNotNamed(const Dataset& d,
                           const std::vector<std::string>& dimensions,
                           const std::string& where_part = "") {
  const DiagnosisReport r = Diagnosed(d);
  EXPECT_EQ(r.verdict, "mismatch_located_unexplained") << DescribeReport(r);
  EXPECT_TRUE(r.findings.empty()) << DescribeReport(r);
  bool listed = false;
  for (const std::string& dim : dimensions) listed |= Lists(r, dim, where_part);
  EXPECT_TRUE(listed) << DescribeReport(r);
}

// +-10 µm on alternate campaigns in time order: campaign means alternate,
// so the runs test sees far too many runs and the lag-1 autocorrelation is
// strongly negative; no recorded quantity alternates with it.
TEST(DiagnosisVerdictTest, AlternatingCampaignOffsetIsLocatedNotNamed) {
  Dataset d = Clean(31);
  const std::vector<int> rank = TimeRank(d);
  for (Measurement& m : d.measurements) {
    m.wear_center_um += rank[m.campaign] % 2 == 1 ? 10.0 : -10.0;
  }
  ExpectLocatedNotNamed(d, {"runs_along_time", "lag1_along_time"});
}

// Wear x 1.08 in alternate stretches of 8 campaigns (a square wave of
// period 16 in time order): runs of same-signed campaign means and a
// positive lag-1 autocorrelation; too fast for a drift or a binned time
// term.
TEST(DiagnosisVerdictTest, FastSquareWaveOverTimeIsLocatedNotNamed) {
  Dataset d = Clean(32, kPaperCampaigns);
  const std::vector<int> rank = TimeRank(d);
  for (Measurement& m : d.measurements) {
    if ((rank[m.campaign] / 8) % 2 == 1) m.wear_center_um *= 1.08;
  }
  ExpectLocatedNotNamed(d, {"lag1_along_time", "runs_along_time"});
}

// The grinder reads the bottom rolls of F7 with an extra N(0, 25 µm)
// error: the mean is untouched, the spread is not.
TEST(DiagnosisVerdictTest, ExtraSpreadAtOnePositionIsLocatedNotNamed) {
  Dataset d = Clean(33);
  Random rng(4242);
  for (Measurement& m : d.measurements) {
    if (m.stand == 7 && m.position == Position::kBottom) {
      m.wear_center_um = std::max(0.0, m.wear_center_um + 25.0 * rng.Normal());
    }
  }
  ExpectLocatedNotNamed(d, {"spread_by_position"}, "F7");
}

// One roll type wears 25 % more at F7 only (roll type x stand, a cell
// the option-1 K structure cannot express): not to be named as a global
// effect of a correlated roll property (hardness, diameter), but as the
// cell it is (the cell vocabulary, docs/diagnosis.md). For a type that runs
// at F6 and F7 only, "x1.25 at F7" and "x1/1.25 at F6" describe the same
// data (its kR takes the rest); the engine offers the cell with fewer
// measurements, so either is right, with the matching multiplier.
TEST(DiagnosisVerdictTest, RollTypeAtOneStandIsNamedAsItsCell) {
  Dataset d = Clean(34, kPaperCampaigns);
  std::map<std::pair<int, std::string>, int>
      type_of;  // (campaign, roll) -> type
  ASSERT_TRUE(std::count(d.roll_types.begin(), d.roll_types.end(), "ICDP-S1"));
  for (const Mount& m : d.mounts)
    type_of[{m.campaign, m.roll_id}] = m.roll_type;
  for (Measurement& m : d.measurements) {
    if (m.stand == 7 &&
        d.roll_types[type_of[{m.campaign, m.roll_id}]] == "ICDP-S1")
      m.wear_center_um *= 1.25;
  }
  const DiagnosisReport r = Diagnosed(d);
  EXPECT_EQ(r.verdict, "missing_physics_found") << DescribeReport(r);
  ASSERT_EQ(r.findings.size(), 1u) << DescribeReport(r);
  const Finding& f = r.findings[0];
  EXPECT_EQ(f.covariate, "roll_type");
  EXPECT_EQ(f.levels, std::vector<std::string>{"ICDP-S1"});
  ASSERT_EQ(f.scope.count("stand"), 1u) << DescribeReport(r);
  const double multiplier = f.parameters.at("multiplier");
  if (f.scope.at("stand") == "F7") {
    EXPECT_NEAR(multiplier, 1.25, 0.06);
  } else {
    EXPECT_EQ(f.scope.at("stand"), "F6");
    EXPECT_NEAR(multiplier, 1 / 1.25, 0.04);
  }
}

// The grade with the most rolled length wears F7 40 % more in proportion
// to its share of the campaign's length there (grade x stand): not to be
// named as a global effect of a correlated pass quantity (contact length,
// reduction). The grade's K coefficient absorbs its mean over the stands,
// so what remains is that grade's cells pulling apart: located in the
// roll position x dominant grade cells of that grade.
TEST(DiagnosisVerdictTest, GradeAtOneStandIsNotNamedAsAGlobalEffect) {
  Dataset d = Clean(35, kPaperCampaigns);
  std::vector<double> grade_len(d.grades.size(), 0.0);
  for (const Pass& p : d.passes) grade_len[p.grade] += p.length_m;
  const int g = static_cast<int>(
      std::max_element(grade_len.begin(), grade_len.end()) - grade_len.begin());
  std::map<int, std::pair<double, double>>
      f7;  // campaign -> (length of g, all)
  for (const Pass& p : d.passes) {
    if (p.stand != 7) continue;
    f7[p.campaign].second += p.length_m;
    if (p.grade == g) f7[p.campaign].first += p.length_m;
  }
  for (Measurement& m : d.measurements) {
    const auto& [len_g, len] = f7[m.campaign];
    if (m.stand == 7 && len > 0) m.wear_center_um *= 1 + 0.4 * len_g / len;
  }
  ExpectLocatedNotNamed(d, {"position_by_grade"},
                        "dominant_grade=" + d.grades[g]);
}

// Colder strip wears F7 rolls more, at F7 only: wear there x
// exp(-0.8 (T - 950 °C) / 100 °C), T the length-weighted strip temperature
// of the campaign at F7. A global temperature term fits it (p tiny, CV
// gain) but its effect is far from the same at F6 and F7: the proxy guard
// must refuse it as a global finding (runner-up "inconsistent across
// stand"); only a term scoped to F7 may name it.
TEST(DiagnosisVerdictTest, StandSpecificEffectIsNotNamedGlobally) {
  Dataset d = Clean(36);
  std::map<int, std::pair<double, double>> f7;  // campaign -> (sum T*len, len)
  for (const Pass& p : d.passes) {
    if (p.stand != 7) continue;
    f7[p.campaign].first += p.temperature_c * p.length_m;
    f7[p.campaign].second += p.length_m;
  }
  for (Measurement& m : d.measurements) {
    const auto& [tl, len] = f7[m.campaign];
    if (m.stand == 7 && len > 0)
      m.wear_center_um *= std::exp(-0.8 * (tl / len - 950) / 100);
  }
  const DiagnosisReport r = Diagnosed(d);
  for (const Finding& f : r.findings) {
    EXPECT_FALSE(f.scope.empty()) << "global finding: " << DescribeReport(r);
    if (!f.scope.empty()) {
      EXPECT_EQ(f.scope.at("stand"), "F7") << DescribeReport(r);
    }
  }
  if (r.findings.empty()) {
    EXPECT_EQ(r.verdict, "mismatch_located_unexplained") << DescribeReport(r);
    bool refused = false;
    for (const RunnerUp& u : r.runners_up) {
      refused |=
          u.reason == "inconsistent across stand" ||
          u.reason.find("located structure remains") != std::string::npos;
    }
    EXPECT_TRUE(refused) << DescribeReport(r);
  }
}

// Clean data: no finding and nothing unexplained in at least 19 of 20
// seeds.
TEST(DiagnosisVerdictTest, CleanDataStaysQuietWithNothingUnexplained) {
  const int num_seeds = test_size::FullOr(20, 4);
  const int need = num_seeds - num_seeds / 20;
  int quiet = 0;
  std::string noisy;
  for (int s = 0; s < num_seeds; ++s) {
    const DiagnosisReport r =
        Diagnosed(Clean(3000 + s, test_size::FullOr(200, 120)));
    if (r.verdict == "no_significant_mismatch") {
      EXPECT_TRUE(r.findings.empty());
      EXPECT_TRUE(r.unexplained.empty());
      ++quiet;
    } else {
      noisy += " seed " + std::to_string(3000 + s) + ": " + DescribeReport(r);
    }
  }
  EXPECT_GE(quiet, need) << noisy;
}

}  // namespace
}  // namespace rollwear
