// The proxy guard's comparisons (docs/diagnosis.md, "The proxy guard"), each
// on a simulated mill where an earlier engine named the wrong thing with a
// tiny p-value (session 10 scorecard): the engine is told nothing, and the
// finding must be the simulator's concealed effect, read from its truth.
//  - a roll type wearing more at one stand, which a contact-length term on
//    that roll type imitated (p = 8e-30): the cell must win, and the
//    contact-length term is a runner-up "no better than the cell";
//  - a grade wearing more at F7 only, in a mill whose grades are measured at
//    F6 and F7 only (twin cells): stated as the place that wears more, with
//    the twin named in the explanation;
//  - a gauge reading low on 46 % of the readings (the most frequent level):
//    the odd gauge out is named, not the two others relative to it;
//  - each roll position's wear rate wandering from campaign to campaign (a
//    random walk, which no term describes) that a binned started_at term
//    imitated: not named, located along time; and a calendar step drift
//    whose binned fit leaves some autocorrelation: still named;
//  - a temperature x speed interaction, whose temperature term the guard
//    refused, read as a specific-force effect at F7 (a shadow): not named;
//  - a hard-grade effect early in the campaign, fitted in one grade only
//    while another hard grade shows it too: not named for that grade; and
//    where no other grade shows it, named with the hard grades whose data
//    cannot tell listed as undetermined;
//  - a calendar drift mixed with a random walk, read as a drift at F7
//    only while F6 drifts too: not named at F7;
//  - a roll type wearing more at F7 with 24 and 27 training readings at F7
//    and F6, too few for a cell then, read as a reduction term on that roll
//    type: the cell must win; the same for a grade at F7 whose cell the
//    cross-validation never saw;
//  - an effect at one roll position (F7 top), which no stand or position
//    scope described (located only): named with that scope;
//  - a speed effect on one roll type, which a coil-length term on it fitted
//    about as well (named `length_m` with p = 3e-16 at 300 campaigns): not
//    named then, the three collinear quantities listed as where it lives;
//    at the paper's size the speed term is named.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/model/covariates.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

// The paper's size, also under the sanitizers (about 1 s per diagnosis in
// Release): the seeds below are the scorecard's, checked at this size.

using simulator_test::Diagnosed;
using simulator_test::DiagnoseSimulated;

bool Lists(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(DiagnosisProxyTest, RollTypeCellWinsOverAContactLengthStandIn) {
  const Diagnosed d = DiagnoseSimulated(104, {"roll_type_stand"});
  ASSERT_EQ(d.sim.truth.effects.size(), 1u);
  const SimulatedEffect& truth = d.sim.truth.effects[0];
  ASSERT_EQ(d.report.verdict, "missing_physics_found");
  ASSERT_EQ(d.report.findings.size(), 1u);
  const Finding& f = d.report.findings[0];
  EXPECT_EQ(f.covariate, "roll_type");
  EXPECT_EQ(f.form, "cell");
  EXPECT_EQ(f.scope, truth.scope);
  ASSERT_FALSE(truth.levels.empty());
  EXPECT_TRUE(Lists(f.levels, truth.levels[0])) << f.explanation;
  EXPECT_NEAR(f.parameters.at("multiplier"), truth.strength, 0.1)
      << f.explanation;
  bool contact_is_runner_up = false;
  for (const RunnerUp& r : d.report.runners_up) {
    if (r.covariate == "contact_length_mm" &&
        r.reason.find("no better than the cell") != std::string::npos) {
      contact_is_runner_up = true;
      // The typed refusal says the same (runners_up[].refusal).
      EXPECT_EQ(r.refusal, RefusalKind::kNoBetterThanCell);
      EXPECT_EQ(r.guard, "");
    }
  }
  EXPECT_TRUE(contact_is_runner_up);
}

TEST(DiagnosisProxyTest, TwinGradeCellIsStatedAsThePlaceThatWearsMore) {
  const Diagnosed d = DiagnoseSimulated(103, {"grade_stand"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_GT(truth.strength, 1.0);  // the truth wears more at its stand
  ASSERT_EQ(d.report.findings.size(), 1u);
  const Finding& f = d.report.findings[0];
  EXPECT_EQ(f.covariate, "grade");
  EXPECT_EQ(f.scope, truth.scope);
  EXPECT_TRUE(Lists(f.levels, truth.levels.at(0)));
  EXPECT_GT(f.parameters.at("multiplier"), 1.0);
  EXPECT_NEAR(f.parameters.at("multiplier"), truth.strength, 0.15);
  // The twin (the other measured stand) is named with the inverse factor.
  EXPECT_NE(f.explanation.find("cannot tell this from rolls of F6"),
            std::string::npos)
      << f.explanation;
}

TEST(DiagnosisProxyTest, TheOddGaugeOutIsNamedNotTheMajority) {
  const Diagnosed d = DiagnoseSimulated(102, {"grinder"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_EQ(truth.levels.size(), 1u);
  ASSERT_LT(truth.strength, 0.0) << truth.description;  // an offset in um, low
  ASSERT_EQ(d.report.findings.size(), 1u);  // no second, spurious finding
  const Finding& f = d.report.findings[0];
  EXPECT_EQ(f.covariate, truth.covariate);
  EXPECT_EQ(f.form, "offset_per_level");
  EXPECT_TRUE(Lists(f.levels, truth.levels[0])) << f.explanation;
  const std::string key = "offset_um[" + truth.levels[0] + "]";
  ASSERT_EQ(f.parameters.count(key), 1u) << f.explanation;
  EXPECT_NEAR(f.parameters.at(key), truth.strength, 4.0) << f.explanation;
}

bool ListsDimension(const std::vector<Unexplained>& u,
                    const std::string& dimension) {
  return std::any_of(u.begin(), u.end(), [&](const Unexplained& x) {
    return x.dimension == dimension;
  });
}

// Seed 104's random walk: a binned started_at term took 33 % of the lag-1
// autocovariance of the campaign means (0.165 -> 0.111) and was named with
// p ~ 1e-9 before the look along time (docs/diagnosis.md, "Along time").
TEST(DiagnosisProxyTest, ARandomWalkIsLocatedAlongTimeNotNamedAsCalendarTime) {
  const Diagnosed d = DiagnoseSimulated(104, {"inexpressible_random_walk"});
  ASSERT_FALSE(d.sim.truth.effects.at(0).expressible);
  EXPECT_TRUE(d.report.findings.empty()) << d.report.findings[0].explanation;
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(ListsDimension(d.report.unexplained, "lag1_along_time"));
  bool refused_along_time = false;
  for (const RunnerUp& r : d.report.runners_up) {
    if ((r.covariate == "started_at" || r.covariate == "measured_at") &&
        r.reason.find("structure along time remains") != std::string::npos) {
      refused_along_time = true;
      EXPECT_EQ(r.refusal, RefusalKind::kProxyGuard);
      EXPECT_EQ(r.guard, "along_time");
    }
  }
  EXPECT_TRUE(refused_along_time);
}

// Seed 105's calendar drift: the binned started_at term leaves r1 = +0.63
// of the campaign means (the step is not exactly on a bin edge) but takes
// 76 % of their lag-1 autocovariance (0.478 -> 0.116): named.
TEST(DiagnosisProxyTest,
     ACalendarDriftIsStillNamedWhenItsFitLeavesSomeAutocorrelation) {
  const Diagnosed d = DiagnoseSimulated(105, {"calendar_drift"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_EQ(d.report.findings.size(), 1u);
  // A drift of the wear rate (rolled_at) is named through the campaign's
  // start, the calendar covariate of the wear-rate vocabulary.
  EXPECT_EQ(d.report.findings[0].covariate,
            truth.covariate == "measured_at" ? "measured_at" : "started_at")
      << truth.covariate << ": " << d.report.findings[0].explanation;
  EXPECT_EQ(d.report.verdict, "missing_physics_found");
}

// The runner-up of `covariate` whose reason contains `why`.
bool RefusedBecause(const DiagnosisReport& r, const std::string& covariate,
                    const std::string& why) {
  return std::any_of(r.runners_up.begin(), r.runners_up.end(),
                     [&](const RunnerUp& u) {
                       return u.covariate == covariate &&
                              u.reason.find(why) != std::string::npos;
                     });
}

// A temperature x speed interaction (inexpressible): the terms that fit it
// best are refused by the guard (their slope changes with the other
// quantity), and a term over a third quantity that passes the guard only
// for want of power but fits worse than a refused one is its shadow, not
// named. Seed 109: contact length fits worse than specific force, which
// the guard refused. Seed 103 (session 11: named specific_force_kn_per_mm
// at F7, p = 2.3e-11) was this test's shadow until session 33; with the
// hinge family's candidates in the round the specific-force term no longer
// passes the multiplicity cut there, and the answer is the same: located
// at temperature, nothing named.
TEST(DiagnosisProxyTest,
     AnInteractionIsNotNamedThroughAShadowOfItsRefusedTerm) {
  for (uint64_t seed : {103u, 109u}) {
    const Diagnosed d = DiagnoseSimulated(seed, {"inexpressible_interaction"});
    ASSERT_FALSE(d.sim.truth.effects.at(0).expressible);
    EXPECT_TRUE(d.report.findings.empty())
        << seed << ": " << d.report.findings[0].explanation;
    EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained") << seed;
    if (seed == 103) {
      // Where it lives: the cold quartile of temperature, one of the two
      // quantities of the interaction.
      EXPECT_TRUE(ListsDimension(d.report.unexplained, "temperature_c"));
    } else {
      EXPECT_TRUE(RefusedBecause(d.report, "contact_length_mm",
                                 "fits worse than specific_force_kn_per_mm"));
    }
  }
}

// Seed 109's interaction (named contact_length_mm, p < 1e-10, until
// session 19): the slope of each candidate along its covariate changes
// with temperature pass by pass, which the campaign-aggregated quartiles
// did not show. Every term but a cell is now split by the pass quartiles
// of the other numeric covariates: refused as inconsistent across
// temperature_c, located there.
TEST(DiagnosisProxyTest, AnInteractionIsRefusedAcrossThePassQuartiles) {
  const Diagnosed d = DiagnoseSimulated(109, {"inexpressible_interaction"});
  ASSERT_FALSE(d.sim.truth.effects.at(0).expressible);
  EXPECT_TRUE(d.report.findings.empty()) << d.report.findings[0].explanation;
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  const bool refused = std::any_of(
      d.report.runners_up.begin(), d.report.runners_up.end(),
      [](const RunnerUp& u) {
        return u.reason == "inconsistent across temperature_c";
      });
  EXPECT_TRUE(refused);
  EXPECT_TRUE(ListsDimension(d.report.unexplained, "effect_by_temperature_c"));
}

// Seed 110 of the same interaction: temperature is refused as inconsistent
// across grade, then speed passes every split at the guard's Bonferroni over
// 36 looks (its temperature quartiles at p = 0.0013 unadjusted) and was
// named at F6 with p = 5.7e-8, while its validation gap got worse. A
// covariate whose own term the round refused is a hypothesis fixed before
// the look: along it the split is tested at the rival level, and speed is
// refused as an interaction with temperature, located there.
TEST(DiagnosisProxyTest, AnInteractionWithARefusedCovariateIsNotNamed) {
  const Diagnosed d = DiagnoseSimulated(110, {"inexpressible_interaction"});
  ASSERT_FALSE(d.sim.truth.effects.at(0).expressible);
  EXPECT_TRUE(d.report.findings.empty()) << d.report.findings[0].explanation;
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  const auto refused_as = [&](const std::string& covariate) {
    return std::any_of(d.report.runners_up.begin(), d.report.runners_up.end(),
                       [&](const RunnerUp& u) {
                         return u.covariate == covariate &&
                                u.guard == "interacts_with_refused";
                       });
  };
  EXPECT_TRUE(refused_as("speed_mps"));
  EXPECT_TRUE(ListsDimension(d.report.unexplained, "temperature_c") ||
              ListsDimension(d.report.unexplained, "effect_by_temperature_c"));
}

// Seed 105's hard grades rolled early in the campaign (session 11: named
// campaign_coils_before "only in grade DP600", p = 1.8e-13): the same term
// added at API-X70, another hard grade, is significant too (LR 17.8), so
// "elsewhere the wear law holds" is false: not named, located by grade.
TEST(DiagnosisProxyTest,
     AHardGradeEffectIsNotNamedForOneGradeWhenAnotherShowsIt) {
  const Diagnosed d = DiagnoseSimulated(105, {"inexpressible_order"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_FALSE(truth.expressible);
  EXPECT_TRUE(d.report.findings.empty()) << d.report.findings[0].explanation;
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(RefusedBecause(d.report, "campaign_coils_before",
                             "not confined to grade DP600"));
  bool at_a_hard_grade = false;
  for (const Unexplained& u : d.report.unexplained) {
    if (u.dimension != "effect_by_grade") continue;
    for (const std::string& g : truth.levels) {
      at_a_hard_grade = at_a_hard_grade || u.where == "grade=" + g;
    }
  }
  EXPECT_TRUE(at_a_hard_grade);
}

// Held-out seed 204 of the same effect: only DP600's early coils show it
// (another hard grade's data reject DP600's effect, docs/diagnosis.md,
// Limits), and the term is named for DP600. The claim "elsewhere the wear
// law holds" is qualified for the hard grades whose data cannot tell: a
// copy of the term there is neither significant nor rejected against a
// copy tied to DP600's parameters. Every grade so listed is a hard grade
// of the truth, and the soft grades, whose data reject the tied copy, are
// not listed.
TEST(DiagnosisProxyTest, AOneGradeScopeListsTheGradesTheDataCannotPlace) {
  const Diagnosed d = DiagnoseSimulated(204, {"inexpressible_order"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  if (d.report.findings.empty()) {
    EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  }
  for (const Finding& f : d.report.findings) {
    if (f.scope.count("grade") == 0) continue;
    ASSERT_FALSE(f.scope_undetermined.empty()) << f.explanation;
    for (const std::string& g : f.scope_undetermined) {
      EXPECT_TRUE(Lists(truth.levels, g)) << g << ": " << f.explanation;
      EXPECT_NE(f.explanation.find(g), std::string::npos) << f.explanation;
    }
    EXPECT_NE(f.explanation.find("the data cannot tell"), std::string::npos)
        << f.explanation;
    EXPECT_EQ(f.explanation.find("elsewhere the wear law holds."),
              std::string::npos)
        << f.explanation;
  }
}

// Seed 101's drift mixed with a random walk (session 11: named started_at
// at F7 only, a wrong scope; docs/diagnosis.md, Limits): F6 drifts too
// (LR 26), so the F7 scope is refused, and the unscoped drift is
// inconsistent across stands (each position wanders its own way): located.
// Since session 17 the strongest unscoped drift is refused first, its
// scale differing across the quartiles of the rolls' service
// (roll_campaigns_before), and the F7 scope is not reached: either
// refusal keeps the wrong scope out.
TEST(DiagnosisProxyTest,
     ADriftFoundAtOneStandIsNotNamedThereWhenTheOtherDriftsToo) {
  const Diagnosed d =
      DiagnoseSimulated(101, {"calendar_drift", "inexpressible_random_walk"});
  for (const Finding& f : d.report.findings) {
    EXPECT_TRUE(f.scope.empty()) << f.covariate << ": " << f.explanation;
  }
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(RefusedBecause(d.report, "started_at", "not confined to F7") ||
              RefusedBecause(d.report, "started_at", "inconsistent across"));
}

// The cell named for a roll type or grade wearing more at one stand, with
// the covariate stand-ins that imitated it as runners-up "no better than the
// cell". Before session 12: roll_type_stand:3 seed 4 at 150 campaigns named
// `reduction` on roll type HSS-S2 (p = 2.6e-16; the roll type had 24 and 27
// training readings at F7 and F6, below the 30 a cell then needed);
// grade_stand seed 207 (a held-out scorecard seed) named `reduction` on
// grade HSLA420 (p = 4.4e-13; its cell had LR 51 but was never
// cross-validated, the three strongest covariates taking the three places).
void ExpectCellNamed(const Diagnosed& d) {
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_EQ(d.report.findings.size(), 1u) << d.report.verdict;
  const Finding& f = d.report.findings[0];
  EXPECT_EQ(f.form, "cell") << f.covariate << ": " << f.explanation;
  EXPECT_EQ(f.covariate, truth.covariate);
  EXPECT_EQ(f.scope, truth.scope) << f.explanation;
  ASSERT_FALSE(truth.levels.empty());
  EXPECT_TRUE(Lists(f.levels, truth.levels[0])) << f.explanation;
  EXPECT_NEAR(f.parameters.at("multiplier"), truth.strength, 0.1)
      << f.explanation;
}

TEST(DiagnosisProxyTest, ARareRollTypeCellIsNamedNotAReductionStandIn) {
  ExpectCellNamed(DiagnoseSimulated(4, {"roll_type_stand:3"}, 150));
}

TEST(DiagnosisProxyTest, AGradeCellOutsideTheTopThreeIsStillComparedAndNamed) {
  const Diagnosed d = DiagnoseSimulated(207, {"grade_stand"});
  ExpectCellNamed(d);
  EXPECT_TRUE(RefusedBecause(d.report, "reduction", "no better than the cell"));
}

// Scoped seed 104: hardness acting at F7 top only. Before session 12 the
// vocabulary had stand and position scopes but not roll positions: the F7
// term was inconsistent across positions and the top term across stands,
// so it was located and not named (gap/floor 1.289).
TEST(DiagnosisProxyTest, AnEffectAtOneRollPositionIsNamedWithThatScope) {
  const Diagnosed d = DiagnoseSimulated(104, {"scoped"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_EQ(d.report.findings.size(), 1u) << d.report.verdict;
  const Finding& f = d.report.findings[0];
  EXPECT_EQ(f.covariate, truth.covariate) << f.explanation;
  const std::map<std::string, std::string> at_f7_top = {{"stand", "F7"},
                                                        {"position", "top"}};
  EXPECT_EQ(truth.scope, at_f7_top);
  EXPECT_EQ(f.scope, truth.scope) << f.explanation;
  EXPECT_NE(f.explanation.find("F7, top rolls"), std::string::npos)
      << f.explanation;
  // The other three roll positions have data enough to reject the term.
  EXPECT_TRUE(f.scope_undetermined.empty()) << f.explanation;
}

// scoped_factor:5 seed 103: speed acting on roll type ICDP-S2 only. Speed,
// coil length and entry thickness move together; at 300 campaigns the
// three terms on ICDP-S2 fit about as well (length first by the
// cross-validation) and none adds significantly to the others, so nothing
// is named and the mismatch is located along them. At 395 campaigns speed
// adds to both rivals and is named.
TEST(DiagnosisProxyTest,
     CollinearCovariatesAreNotNamedUntilTheDataTellThemApart) {
  const Diagnosed few = DiagnoseSimulated(103, {"scoped_factor:5"}, 300);
  const SimulatedEffect& truth = few.sim.truth.effects.at(0);
  ASSERT_EQ(truth.covariate, "speed_mps");
  for (const Finding& f : few.report.findings) {
    EXPECT_EQ(f.covariate, truth.covariate) << f.explanation;
  }
  if (few.report.findings.empty()) {
    EXPECT_EQ(few.report.verdict, "mismatch_located_unexplained");
    EXPECT_TRUE(
        RefusedBecause(few.report, "length_m", "not distinguishable from"));
    for (const RunnerUp& u : few.report.runners_up) {
      const bool says =
          u.reason.find("not distinguishable from") != std::string::npos;
      EXPECT_EQ(says, u.refusal == RefusalKind::kNotDistinguishable)
          << u.covariate << ": " << u.reason;
    }
    // One place, along the collinear quantities, speed among them.
    const auto along = std::find_if(
        few.report.unexplained.begin(), few.report.unexplained.end(),
        [](const Unexplained& u) { return u.test == "encompassing_lr"; });
    ASSERT_NE(along, few.report.unexplained.end());
    EXPECT_EQ(along->where.rfind("roll type ICDP-S2: along ", 0), 0u)
        << along->where;
    EXPECT_NE(along->where.find("speed_mps"), std::string::npos)
        << along->where;
    EXPECT_GT(along->mean_residual_um, 1.0);
  }
  const Diagnosed paper = DiagnoseSimulated(103, {"scoped_factor:5"});
  ASSERT_EQ(paper.report.findings.size(), 1u) << paper.report.verdict;
  EXPECT_EQ(paper.report.findings[0].covariate, "speed_mps");
  EXPECT_EQ(paper.report.findings[0].scope, truth.scope);
}

// Two factor combinations the K structure cannot express at once: a grade
// wearing more at one stand and a roll type wearing more at one stand
// (grade_stand+roll_type_stand, seed 103). Before session 16 one cell per
// diagnosis was offered: an independent generator's two-cell mills had the
// second cell named as reduction or contact length on the grade (p 1e-8 to
// 1e-13 in 8 of 10 seeds). Both must now be named as their cells.
TEST(DiagnosisProxyTest, TwoCellsAreBothNamedAsCells) {
  const Diagnosed d =
      DiagnoseSimulated(103, {"grade_stand", "roll_type_stand"});
  ASSERT_EQ(d.sim.truth.effects.size(), 2u);
  ASSERT_EQ(d.report.findings.size(), 2u) << d.report.verdict;
  for (const SimulatedEffect& truth : d.sim.truth.effects) {
    const auto f = std::find_if(
        d.report.findings.begin(), d.report.findings.end(),
        [&](const Finding& x) { return x.covariate == truth.covariate; });
    ASSERT_NE(f, d.report.findings.end()) << truth.covariate;
    EXPECT_EQ(f->form, "cell");
    EXPECT_EQ(f->scope, truth.scope) << f->explanation;
    EXPECT_TRUE(Lists(f->levels, truth.levels.at(0))) << f->explanation;
    EXPECT_NEAR(f->parameters.at("multiplier"), truth.strength, 0.1)
        << f->explanation;
  }
}

// A temperature effect on the passes rolled without lubrication only
// (inexpressible_lubrication, seed 101): an unscoped temperature term fits
// it with p = 1e-65, and no scope of the vocabulary is the lubrication
// flag. The guard splits the term's contribution by the flag of its passes
// (diagnosis_split.cc): its scale on dry passes differs from that on
// lubricated ones, so nothing is named and the place is located.
TEST(DiagnosisProxyTest, AnEffectOnDryPassesOnlyIsLocatedNotNamedEverywhere) {
  const Diagnosed d = DiagnoseSimulated(101, {"inexpressible_lubrication"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  ASSERT_EQ(truth.mismatch, "temperature_c x lubrication");
  ASSERT_NE(truth.description.find("without lubrication"), std::string::npos);
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(d.report.findings.empty());
  EXPECT_TRUE(RefusedBecause(d.report, "temperature_c",
                             "inconsistent across lubrication"));
  const auto u =
      std::find_if(d.report.unexplained.begin(), d.report.unexplained.end(),
                   [](const Unexplained& x) {
                     return x.dimension == "effect_by_lubrication";
                   });
  ASSERT_NE(u, d.report.unexplained.end());
  EXPECT_EQ(u->where, "lubrication=off");
  EXPECT_LT(u->p_adjusted, 1e-10);
}

// The same family on held-out seed 201: campaign growth on dry passes only.
// Its mean is a flag effect, and the lubrication flag was named (as in 3
// of held-out seeds 201-210) until session 17: a term with one multiplier
// on a set of passes is now also split by the quartiles of every numeric
// pass-level covariate, and on dry passes late in the campaign it is far
// stronger than early. The strongest inconsistent split must be the
// truth's covariate.
TEST(DiagnosisProxyTest, AnEffectOnDryPassesIsNotNamedAsTheLubricationFlag) {
  const Diagnosed d = DiagnoseSimulated(201, {"inexpressible_lubrication"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  const std::string covariate =
      truth.mismatch.substr(0, truth.mismatch.find(" x "));
  ASSERT_EQ(truth.mismatch, covariate + " x lubrication");
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  for (const Finding& f : d.report.findings)
    EXPECT_NE(f.covariate, "lubrication");
  const auto first = std::find_if(
      d.report.runners_up.begin(), d.report.runners_up.end(),
      [](const RunnerUp& r) { return r.covariate == "lubrication"; });
  ASSERT_NE(first, d.report.runners_up.end());
  EXPECT_EQ(first->reason, "inconsistent across " + covariate);
  const auto u =
      std::find_if(d.report.unexplained.begin(), d.report.unexplained.end(),
                   [&](const Unexplained& x) {
                     return x.dimension == "effect_by_" + covariate;
                   });
  ASSERT_NE(u, d.report.unexplained.end());
  EXPECT_EQ(u->where.rfind(covariate + "=Q", 0), 0u) << u->where;
  EXPECT_LT(u->p_adjusted, 1e-10);
}

// Coils rolled at night (22-06 h UTC) wearing more (inexpressible_night_shift,
// seed 101): no recorded quantity but the time of day follows it. Before
// session 16 the answer was `no_significant_mismatch` with the validation
// gap far above the noise floor; now the time of day is a breakdown of its
// own (diagnosis_locate.cc) and the night block is where it lives.
TEST(DiagnosisProxyTest, ANightShiftIsLocatedAtTheTimeOfDay) {
  const Diagnosed d = DiagnoseSimulated(101, {"inexpressible_night_shift:0"});
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(d.report.findings.empty());
  ASSERT_FALSE(d.report.unexplained.empty());
  const Unexplained& u = d.report.unexplained.front();  // strongest first
  EXPECT_EQ(u.dimension, "time_of_day");
  EXPECT_EQ(u.where, "time_of_day=00-06 h UTC");
  EXPECT_GT(u.mean_residual_um, 10.0);  // the night wears more
  EXPECT_LT(u.p_adjusted, 1e-10);
}

// About one physical roll in ten wearing more whenever it is mounted
// (inexpressible_bad_rolls, seed 101), its hardness and diameter as
// recorded: only its serial follows it. The roll_id breakdown (session 16;
// `no_significant_mismatch` before on an independent generator's bad roll)
// must locate it at a roll whose readings the simulator made wear more.
TEST(DiagnosisProxyTest, ABadRollIsLocatedAtItsSerial) {
  const Diagnosed d = DiagnoseSimulated(101, {"inexpressible_bad_rolls"});
  const double m = d.sim.truth.effects.at(0).strength;
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(d.report.findings.empty());
  ASSERT_FALSE(d.report.unexplained.empty());
  const Unexplained& u = d.report.unexplained.front();
  EXPECT_EQ(u.dimension, "roll_id");
  EXPECT_LT(u.p_adjusted, 1e-6);
  // Every reading of the listed roll carries the multiplier: against the
  // same seed without the effect (the families draw from their own random
  // streams, so the mill is the same; the extra wear changes the roll's
  // later diameter a little, hence 0.005 and not exactly).
  const Simulation clean = simulator_test::Simulated(101, kPaperCampaigns, {});
  ASSERT_EQ(clean.truth.noise_free_wear_um.size(),
            d.sim.truth.noise_free_wear_um.size());
  const std::string prefix = "roll_id=";
  ASSERT_EQ(u.where.rfind(prefix, 0), 0u) << u.where;
  const std::string roll = u.where.substr(prefix.size());
  int readings = 0;
  for (size_t i = 0; i < d.sim.data.measurements.size(); ++i) {
    if (d.sim.data.measurements[i].roll_id != roll) continue;
    ++readings;
    EXPECT_NEAR(
        d.sim.truth.noise_free_wear_um[i] / clean.truth.noise_free_wear_um[i],
        m, 0.005);
  }
  EXPECT_GE(readings, 5);
}

// A roll wearing more the more campaigns it has served
// (inexpressible_roll_service, seed 102). Rolls serve in turn, so a roll's
// service follows the calendar: this seed was named `started_at` before
// session 17 (4 of seeds 101-105), as an independent generator's such mills
// were (p 1e-98 to 1e-128, 6 of 6). A roll's earlier campaigns
// (roll_campaigns_before) are now a locate-only rival: tested, listed where the
// mismatch lives, never named; and a calendar term must add to it to be named.
TEST(DiagnosisProxyTest, ARollsServiceIsLocatedNotNamedAsCalendarTime) {
  // Seed 102 is the step variant: x(1 + s) from a roll's third campaign.
  const Diagnosed d = DiagnoseSimulated(102, {"inexpressible_roll_service"});
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  EXPECT_TRUE(d.report.findings.empty());
  // Where it lives: the guard's entry for the refused roll-service term
  // (its size the rms of what it adds), and the final look's quartile of
  // the youngest rolls, which wear less than the model says (it averages
  // over every roll's service).
  const auto entry = [&](const std::string& where) {
    return std::find_if(d.report.unexplained.begin(),
                        d.report.unexplained.end(), [&](const Unexplained& u) {
                          return u.dimension == "roll_campaigns_before" &&
                                 u.where.rfind(where, 0) == 0;
                        });
  };
  const auto term = entry("each roll's earlier campaigns (roll_id)");
  ASSERT_NE(term, d.report.unexplained.end());
  EXPECT_GT(term->mean_residual_um, 10.0);
  EXPECT_LT(term->p_adjusted, 1e-20);
  const auto young = entry("roll_campaigns_before=Q1");
  ASSERT_NE(young, d.report.unexplained.end());
  EXPECT_LT(young->mean_residual_um, -10.0);
  EXPECT_LT(young->p_adjusted, 1e-10);
  // The calendar term was significant, and refused (its strongest form)
  // for the roll's service: inconsistent across it, or not distinguishable
  // from it; weaker forms may be refused as its shadows.
  const auto first = std::find_if(
      d.report.runners_up.begin(), d.report.runners_up.end(),
      [](const RunnerUp& r) { return r.covariate == "started_at"; });
  ASSERT_NE(first, d.report.runners_up.end());
  EXPECT_NE(first->reason.find("roll_campaigns_before"), std::string::npos)
      << first->reason;
}

// The same effect when the mill records each roll's regrinds in a column of
// mounts.csv (here: the count RollCampaignsBefore gives, as an independent
// generator's `regrinds`): the recorded column is the quantity and is
// named; the locate-only rival describes the same data and adds nothing to
// it (before the reverse encompassing test, session 17, it was refused as
// "not distinguishable from roll_campaigns_before").
// The locate-only rival is not offered as an alternative name either (it
// was, in the finding's `alternatives`, until session 19). Variant 1 is a
// step (x(1 + s) from the third campaign on): named as the same column, a
// step up (its quantile bins 1, 1.21, 1.20, 1.21 read as
// "saturating_growth" until session 19).
StatusOr<DiagnosisReport> DiagnoseWithRegrinds(const std::string& effect) {
  Simulation sim = simulator_test::Simulated(101, kPaperCampaigns, {effect});
  const std::vector<int> n = RollCampaignsBefore(sim.data);
  sim.data.mount_extra.numeric_names.push_back("regrinds");
  sim.data.mount_extra.numeric.emplace_back(n.begin(), n.end());
  return Diagnose(sim.data, DiagnosisOptions{});
}
TEST(DiagnosisProxyTest,
     ARecordedRegrindCountIsNamedThoughARollsServiceIsItsTwin) {
  const std::pair<const char*, const char*> cases[] = {
      {"inexpressible_roll_service:0", "increasing"},
      {"inexpressible_roll_service:1", "step_up"}};
  for (const auto& [effect, shape] : cases) {
    SCOPED_TRACE(effect);
    const StatusOr<DiagnosisReport> r = DiagnoseWithRegrinds(effect);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_EQ(r->verdict, "missing_physics_found");
    ASSERT_FALSE(r->findings.empty());
    const Finding& f = r->findings.front();
    EXPECT_EQ(f.covariate, "regrinds");
    EXPECT_EQ(f.shape, shape) << f.explanation;
    EXPECT_TRUE(f.scope.empty());
    EXPECT_LT(f.p_value, 1e-10);
    for (const std::string& a : f.alternatives) {
      EXPECT_NE(a, "roll_campaigns_before");
    }
    for (const Finding& g : r->findings) EXPECT_NE(g.covariate, "started_at");
  }
}

// Two of the four roll types that run at both stands wearing more at one
// stand (roll_type_pair_stand, seed 103: ICDP-S1 and HiCr-S2 at F6). In a
// two-stand mill that is the same data as the other two types wearing as
// much more at the other stand. Before session 17 the engine named one of
// the pairs in 4 of seeds 101-105, whichever its fit landed on (here the
// truth's; an independent generator's `two_types_f7` got the other pair in
// 7 of 10). Neither is identified: the set is withdrawn and located with
// both descriptions.
TEST(DiagnosisProxyTest,
     TwoRollTypesAtOneStandAreLocatedWithTheirEquivalentPair) {
  const Diagnosed d = DiagnoseSimulated(103, {"roll_type_pair_stand"});
  const SimulatedEffect& truth = d.sim.truth.effects.at(0);
  EXPECT_EQ(d.report.verdict, "mismatch_located_unexplained");
  for (const Finding& f : d.report.findings)
    EXPECT_NE(f.covariate, "roll_type");
  const auto u = std::find_if(
      d.report.unexplained.begin(), d.report.unexplained.end(),
      [](const Unexplained& x) { return x.dimension == "stand_by_roll_type"; });
  ASSERT_NE(u, d.report.unexplained.end());
  // Both pairs, each at its stand: the truth's and the other two shared
  // types at the other stand.
  const std::string stand = truth.scope.at("stand");
  const std::string other = stand == "F7" ? "F6" : "F7";
  for (const std::string& type : truth.levels) {
    EXPECT_NE(u->where.find(type), std::string::npos) << u->where;
  }
  EXPECT_NE(u->where.find(" at " + stand), std::string::npos) << u->where;
  EXPECT_NE(u->where.find(" at " + other), std::string::npos) << u->where;
  int shared = 0;
  for (const char* type : {"ICDP-S1", "ICDP-S2", "HiCr-S2", "HSS-S2"}) {
    shared += u->where.find(type) != std::string::npos;
  }
  EXPECT_EQ(shared, 4) << u->where;
  EXPECT_LT(u->p_adjusted, 1e-6);
  EXPECT_GT(u->mean_residual_um, 5.0);
  // The withdrawn cells are listed with why.
  EXPECT_TRUE(std::any_of(
      d.report.runners_up.begin(), d.report.runners_up.end(),
      [](const RunnerUp& r) { return r.reason.rfind("withdrawn: ", 0) == 0; }));
}

// A grade wearing more at one roll position only (grade_roll_position,
// seed 102: S355 at F6/top). Before session 16 the cells were (stand or
// position) x (roll type or grade); an independent generator's grade at
// F7/bottom was named as the grade's cell on every bottom roll (p 9.5e-6)
// in one seed of ten. Roll-position cells are offered now: the cell must
// be named at its roll position, multiplier within 0.1.
TEST(DiagnosisProxyTest, AGradeAtOneRollPositionIsNamedAsThatCell) {
  ExpectCellNamed(DiagnoseSimulated(102, {"grade_roll_position"}));
}

}  // namespace
}  // namespace rollwear
