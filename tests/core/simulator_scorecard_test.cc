// The scorecard's scoring (core/report/scorecard.h) on hand-built reports:
// named right needs covariate, scope and levels; anything else a finding
// names is wrong physics (a finding on the right covariate and scope that
// names no level is neither); equivalent covariate names only within a class;
// an inexpressible effect is named right only by "unexplained" without a
// finding; and on one small simulated clean case, the noise floor is the
// truth's.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/report/scorecard.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

Finding Found(std::string covariate,
              std::map<std::string, std::string> scope = {},
              std::vector<std::string> levels = {}) {
  Finding f;
  f.covariate = std::move(covariate);
  f.scope = std::move(scope);
  f.levels = std::move(levels);
  return f;
}

DiagnosisReport Report(std::vector<Finding> findings, std::string verdict) {
  DiagnosisReport r;
  r.findings = std::move(findings);
  r.verdict = std::move(verdict);
  r.final_gap_val_um = 12;
  // Two validation points with |measured - noise-free| 8 and 12: floor 10.
  DiagnosisPoint a, b, train;
  a.campaign_id = "C0001";
  a.stand = 7;
  a.validation = true;
  a.measured_um = 108;
  b = a;
  b.position = Position::kBottom;
  b.measured_um = 88;
  train = a;
  train.validation = false;
  train.measured_um = 500;
  r.points = {a, b, train};
  return r;
}

ScoreTruth Truth(std::vector<ConcealedEffect> effects) {
  ScoreTruth t;
  t.effects = std::move(effects);
  t.noise_free_um[{"C0001", 7, 0}] = 100;
  t.noise_free_um[{"C0001", 7, 1}] = 100;
  return t;
}

const ConcealedEffect kGradeF7 = {"grade_stand", "grade", {{"stand", "F7"}},
                                  {"S355"},      true,    ""};

TEST(ScorecardTest, GradeAtF7NamedRightOnlyWithScopeAndLevel) {
  const ScoreTruth truth = Truth({kGradeF7});
  CaseScore s = ScoreCase("grade_stand", 3,
                          Report({Found("grade", {{"stand", "F7"}}, {"S355"})},
                                 "missing_physics_found"),
                          truth);
  EXPECT_TRUE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 0);
  EXPECT_FALSE(s.clean);
  EXPECT_NEAR(s.noise_floor_um, 10, 1e-12);
  EXPECT_NEAR(s.gap_ratio, 1.2, 1e-12);
  EXPECT_EQ(s.findings, std::vector<std::string>{"grade {stand:F7} [S355]"});

  // The proxy the issue saw: contact length, peaked. Wrong physics.
  s = ScoreCase("grade_stand", 3,
                Report({Found("contact_length_mm")}, "missing_physics_found"),
                truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  // Right covariate, no scope: the wrong scope is wrong physics too.
  s = ScoreCase("grade_stand", 3,
                Report({Found("grade", {}, {"S355"})}, "missing_physics_found"),
                truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  // Right cell, no level named: which grade is not said (says less, not
  // something wrong: not wrong physics).
  s = ScoreCase("grade_stand", 3,
                Report({Found("grade", {{"stand", "F7"}})},
                       "missing_physics_found"),
                truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 0);
  // Right cell, wrong grade.
  s = ScoreCase("grade_stand", 3,
                Report({Found("grade", {{"stand", "F7"}}, {"C45"})},
                       "missing_physics_found"),
                truth);
  EXPECT_FALSE(s.named_right);
  // Right finding plus a spurious second one.
  s = ScoreCase(
      "grade_stand", 3,
      Report({Found("grade", {{"stand", "F7"}}, {"S355"}), Found("force_kn")},
             "missing_physics_found"),
      truth);
  EXPECT_TRUE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
}

// Two grades wearing F7 more (grade_pair_stand): named right as two cell
// findings, one level each; one of them alone says the other follows the
// law, which is wrong physics; a third grade beside them is wrong too.
TEST(ScorecardTest, APairOfCellsIsNamedRightOnlyAsBoth) {
  const ScoreTruth truth = Truth({{"grade_pair_stand",
                                   "grade",
                                   {{"stand", "F7"}},
                                   {"S355", "CQ"},
                                   true,
                                   ""}});
  const Finding s355 = Found("grade", {{"stand", "F7"}}, {"S355"});
  const Finding cq = Found("grade", {{"stand", "F7"}}, {"CQ"});
  CaseScore s = ScoreCase("grade_pair_stand", 1,
                          Report({s355, cq}, "missing_physics_found"), truth);
  EXPECT_TRUE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 0);
  s = ScoreCase("grade_pair_stand", 1, Report({s355}, "missing_physics_found"),
                truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  s = ScoreCase("grade_pair_stand", 1,
                Report({s355, cq, Found("grade", {{"stand", "F7"}}, {"C45"})},
                       "missing_physics_found"),
                truth);
  EXPECT_TRUE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  // At the other stand: not this effect.
  s = ScoreCase("grade_pair_stand", 1,
                Report({Found("grade", {{"stand", "F6"}}, {"S355"}), cq},
                       "missing_physics_found"),
                truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 2);
}

// Wear per coil and a growth along the campaign share the coil count: only
// the finding of the truth's form names it, either way round.
TEST(ScorecardTest, WearPerCoilIsRightOnlyInItsForm) {
  const ConcealedEffect per_coil = {
      "per_coil", "campaign_coils_before", {{"stand", "F6"}}, {}, true, "",
      "per_coil"};
  const ConcealedEffect growth = {
      "campaign_growth", "campaign_length_before_m", {}, {}, true, ""};
  Finding coils = Found("campaign_coils_before", {{"stand", "F6"}});
  coils.form = "per_coil";
  Finding rising = Found("campaign_coils_before", {{"stand", "F6"}});
  rising.form = "log_linear";
  CaseScore s =
      ScoreCase("per_coil", 1, Report({coils}, "missing_physics_found"),
                Truth({per_coil}));
  EXPECT_TRUE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 0);
  s = ScoreCase("per_coil", 1, Report({rising}, "missing_physics_found"),
                Truth({per_coil}));
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  coils.scope.clear();
  rising.scope.clear();
  s = ScoreCase("campaign_growth", 1, Report({coils}, "missing_physics_found"),
                Truth({growth}));
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  s = ScoreCase("campaign_growth", 1, Report({rising}, "missing_physics_found"),
                Truth({growth}));
  EXPECT_TRUE(s.named_right);
}

TEST(ScorecardTest, EquivalentNamesOnlyWithinTheirClass) {
  EXPECT_TRUE(SameCovariate("rolled_at", "started_at"));
  // A drift of the reading is not a drift of the wear rate.
  EXPECT_FALSE(SameCovariate("measured_at", "started_at"));
  EXPECT_FALSE(SameCovariate("measured_at", "rolled_at"));
  EXPECT_TRUE(
      SameCovariate("campaign_length_before_m", "campaign_coils_before"));
  EXPECT_FALSE(SameCovariate("hours_since_mount", "campaign_length_before_m"));
  EXPECT_FALSE(SameCovariate("temperature_c", "speed_mps"));
  EXPECT_FALSE(SameCovariate("", ""));
  EXPECT_TRUE(SameCovariate("grinder", "grinder"));
}

// A report with the third verdict and one unexplained check of `dimension`.
DiagnosisReport Unexplained1(const std::string& dimension) {
  DiagnosisReport r = Report({}, "mismatch_located_unexplained");
  Unexplained u;
  u.dimension = dimension;
  u.where = dimension + " (test)";
  u.test = "anova";
  u.p_value = 1e-8;
  u.p_adjusted = 1e-6;
  r.unexplained.push_back(u);
  return r;
}

TEST(ScorecardTest, InexpressibleIsRightOnlyAsUnexplained) {
  const ScoreTruth truth = Truth(
      {{"inexpressible_order", "", {}, {}, false, "campaign order x grade"}});
  CaseScore s = ScoreCase("inexpressible_order", 1,
                          Unexplained1("position_by_grade"), truth);
  EXPECT_TRUE(s.named_right);
  EXPECT_FALSE(s.expressible);
  EXPECT_EQ(s.wrong_physics, 0);
  s = ScoreCase(
      "inexpressible_order", 1,
      Report({Found("campaign_coils_before")}, "missing_physics_found"), truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  s = ScoreCase("inexpressible_order", 1, Report({}, "no_significant_mismatch"),
                truth);
  EXPECT_FALSE(s.named_right);
  // A name qualified by the levels the data cannot place is still a name:
  // wrong for an inexpressible effect, and the listing shows the levels.
  Finding qualified = Found("campaign_coils_before", {{"grade", "DP600"}});
  qualified.scope_undetermined = {"API-X65", "API-X70"};
  s = ScoreCase("inexpressible_order", 1,
                Report({qualified}, "missing_physics_found"), truth);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 1);
  EXPECT_EQ(s.findings,
            std::vector<std::string>{
                "campaign_coils_before {grade:DP600} ?API-X65,API-X70"});
}

TEST(ScorecardTest, InexpressibleNeedsTheRightLocation) {
  const ScoreTruth order = Truth(
      {{"inexpressible_order", "", {}, {}, false, "campaign order x grade"}});
  // The verdict alone, with nothing located, is not enough.
  EXPECT_FALSE(ScoreCase("inexpressible_order", 1,
                         Report({}, "mismatch_located_unexplained"), order)
                   .named_right);
  // Either part of the location counts: the order within the campaign ...
  EXPECT_TRUE(ScoreCase("inexpressible_order", 1,
                        Unexplained1("campaign_coils_before"), order)
                  .named_right);
  EXPECT_TRUE(ScoreCase("inexpressible_order", 1, Unexplained1("dominant_grade"), order)
                  .named_right);
  // The grade x campaign-order check locates both parts at once.
  EXPECT_TRUE(ScoreCase("inexpressible_order", 1,
                        Unexplained1("grade_by_campaign_order"), order)
                  .named_right);
  const ScoreTruth interaction_only = Truth({{"inexpressible_interaction",
                                              "",
                                              {},
                                              {},
                                              false,
                                              "temperature_c x speed_mps"}});
  EXPECT_FALSE(ScoreCase("inexpressible_interaction", 1,
                         Unexplained1("grade_by_campaign_order"),
                         interaction_only)
                   .named_right);
  // ... but not a place the effect does not live.
  CaseScore s = ScoreCase("inexpressible_order", 1, Unexplained1("spread_by_position"), order);
  EXPECT_FALSE(s.named_right);
  EXPECT_EQ(s.wrong_physics, 0);
  EXPECT_FALSE(ScoreCase("inexpressible_order", 1, Unexplained1("time_scale_8"), order)
                   .named_right);

  const ScoreTruth interaction = Truth({{"inexpressible_interaction", "", {}, {}, false,
                                         "temperature_c x speed_mps"}});
  EXPECT_TRUE(ScoreCase("inexpressible_interaction", 1, Unexplained1("speed_mps"),
                        interaction)
                  .named_right);
  EXPECT_FALSE(ScoreCase("inexpressible_interaction", 1,
                         Unexplained1("roll_position"), interaction)
                   .named_right);

  // Time order of campaigns, by roll position; calendar periods.
  const ScoreTruth walk = Truth({{"inexpressible_random_walk", "", {}, {}, false,
                                  "time (campaign order), by roll position"}});
  EXPECT_TRUE(ScoreCase("inexpressible_random_walk", 1, Unexplained1("lag1_along_time"), walk)
                  .named_right);
  EXPECT_TRUE(ScoreCase("inexpressible_random_walk", 1,
                        Unexplained1("position_by_time_half"), walk)
                  .named_right);
  EXPECT_FALSE(ScoreCase("inexpressible_random_walk", 1,
                         Unexplained1("campaign_coils_before"), walk)
                   .named_right);
  const ScoreTruth bursts = Truth({{"inexpressible_bursts", "", {}, {}, false,
                                    "time (spread by calendar period)"}});
  EXPECT_TRUE(ScoreCase("inexpressible_bursts", 1, Unexplained1("spread_by_time"), bursts)
                  .named_right);
  EXPECT_TRUE(ScoreCase("inexpressible_bursts", 1,
                        Unexplained1("spread_time_scale_16"), bursts)
                  .named_right);
  EXPECT_FALSE(ScoreCase("inexpressible_bursts", 1, Unexplained1("dominant_grade"), bursts)
                   .named_right);
  // Extra wear after restarts: located at the flag, or by the guard's
  // refusal across it; not along hours in service, which stands in for it.
  const ScoreTruth restart = Truth(
      {{"inexpressible_restart", "", {}, {}, false, "coils after a stop"}});
  for (const char* at : {"after_stop", "effect_by_after_stop"}) {
    EXPECT_TRUE(ScoreCase("inexpressible_restart", 1, Unexplained1(at), restart)
                    .named_right)
        << at;
  }
  EXPECT_FALSE(ScoreCase("inexpressible_restart", 1,
                         Unexplained1("hours_since_mount"), restart)
                   .named_right);

  // A covariate effect on dry passes only: located by the guard's refusal
  // across the lubrication flag, or along the covariate; not by a grade.
  const ScoreTruth dry = Truth({{"inexpressible_lubrication", "", {}, {}, false,
                                 "temperature_c x lubrication"}});
  EXPECT_TRUE(ScoreCase("inexpressible_lubrication", 1,
                        Unexplained1("effect_by_lubrication"), dry)
                  .named_right);
  EXPECT_TRUE(ScoreCase("inexpressible_lubrication", 1, Unexplained1("temperature_c"), dry)
                  .named_right);
  EXPECT_FALSE(ScoreCase("inexpressible_lubrication", 1,
                         Unexplained1("effect_by_grade"), dry)
                   .named_right);
}

TEST(ScorecardTest, MismatchPartsSplitAtCrossAndBy) {
  EXPECT_EQ(MismatchParts("campaign order x grade"),
            (std::vector<std::string>{"campaign order", "grade"}));
  EXPECT_EQ(MismatchParts("time (campaign order), by roll position"),
            (std::vector<std::string>{"time (campaign order)", "roll position"}));
  EXPECT_EQ(MismatchParts("time (spread by calendar period)"),
            (std::vector<std::string>{"time (spread by calendar period)"}));
}

TEST(ScorecardTest, SummaryCountsAndTable) {
  const ScoreTruth clean = Truth({});
  std::vector<CaseScore> cases = {
      ScoreCase("clean", 1, Report({}, "no_significant_mismatch"), clean),
      ScoreCase("clean", 2,
                Report({Found("speed_mps")}, "missing_physics_found"), clean),
      ScoreCase("grade_stand", 1,
                Report({Found("grade", {{"stand", "F7"}}, {"S355"})},
                       "missing_physics_found"),
                Truth({kGradeF7})),
  };
  EXPECT_TRUE(cases[0].clean);
  EXPECT_EQ(cases[1].wrong_physics, 1);
  const std::vector<EffectScore> s = Summarise(cases);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].effect, "clean");
  EXPECT_EQ(s[0].cases, 2);
  EXPECT_EQ(s[0].quiet, 1);
  EXPECT_EQ(s[0].with_wrong_physics, 1);
  EXPECT_EQ(s[1].named_right, 1);
  const std::string table = ScorecardTable(s);
  EXPECT_NE(table.find("| clean | 2 | - | 1/2 | 1/2 | 1.200 | 1.200 |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| grade_stand | 1 | 1/1 | 0/1 | 0/1 |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| **all** | 3 | 1/1 | 1/3 | 1/3 |"), std::string::npos)
      << table;
}

// One small real case: the scorecard's noise floor over the validation
// points is the truth's grinder noise (mean |e| of N(0, 8) is 6.4 um, with
// 9 % roll scatter on ~150 um more), and the clean report has no wrong
// physics to score.
TEST(ScorecardTest, SmallCleanCaseFloorFromTruth) {
  const Simulation sim = simulator_test::Simulated(101, 100);
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ScoreTruth truth;
  for (size_t i = 0; i < sim.data.measurements.size(); ++i) {
    const Measurement& m = sim.data.measurements[i];
    truth.noise_free_um[{sim.data.campaigns[m.campaign].id, m.stand,
                         static_cast<int>(m.position)}] =
        sim.truth.noise_free_wear_um[i];
  }
  const CaseScore s = ScoreCase("clean", 101, *r, truth);
  EXPECT_TRUE(s.clean);
  EXPECT_NEAR(s.noise_floor_um, sim.truth.noise_floor_um,
              0.25 * sim.truth.noise_floor_um);
  EXPECT_EQ(s.wrong_physics, s.num_findings);
  EXPECT_GT(s.gap_ratio, 0.8);
  EXPECT_LT(s.gap_ratio, 1.3);
}

}  // namespace
}  // namespace rollwear
