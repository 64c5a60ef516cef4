// The per-roll family of the diagnosis (diagnosis_roll_family.cc): a mill
// whose physical rolls each wear by their own lifelong factor is diagnosed
// as roll_wear_resistance with the spread it was drawn with, and the
// adopted model predicts held-out campaigns better; without such factors,
// and where a calendar step of the wear rate could pass for roll scatter,
// no per-roll finding is made. The adopted roll-effect term means the same
// in the refit of `calibrate --terms` and coil by coil in the predictor.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/fit/term_refit.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

constexpr int kRollFamilyCampaigns = test_size::FullOr(395, 200);
// Under the sanitizers one seed of each (test_size.h); two and three else.
constexpr int kRollFamilySeeds = test_size::FullOr(3, 1);

Simulation SimulatedRollMill(uint64_t seed, double roll_factor_sd,
                     std::vector<std::string> effects = {}) {
  return simulator_test::Simulated(seed, kRollFamilyCampaigns,
                                   std::move(effects), 0, roll_factor_sd);
}

const Finding* RollWearFinding(const DiagnosisReport& r) {
  for (const Finding& f : r.findings) {
    if (f.mechanism == "roll_wear_resistance") return &f;
  }
  return nullptr;
}

// Pearson correlation of the fitted log-multipliers with the true log
// factors over the rolls the term knows.
double RollCorrelationWithTruth(const ModelTerm& t, const SimulationTruth& truth) {
  std::vector<double> a, b;
  for (int l = 0; l < t.num_levels; ++l) {
    auto it = truth.roll_wear_factor.find(t.levels[l]);
    if (it == truth.roll_wear_factor.end()) continue;
    a.push_back(t.params[l]);
    b.push_back(std::log(it->second));
  }
  return simulator_test::Correlation(a, b);
}

TEST(DiagnosisRollFamilyTest, EachRollsOwnWearFactorIsNamedAndImprovesHeldOut) {
  for (uint64_t seed = 41; seed < 41 + std::min(kRollFamilySeeds, 2); ++seed) {
    const Simulation sim = SimulatedRollMill(seed, 0.2);
    StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const Finding* f = RollWearFinding(*r);
    ASSERT_NE(f, nullptr) << seed << ": " << simulator_test::DescribeReport(*r);
    EXPECT_EQ(f->form, "roll_effect");
    EXPECT_EQ(f->covariate, "roll_id");
    EXPECT_LT(f->p_value, 1e-6);
    // Drawn with sd 0.2 of the log factor.
    EXPECT_NEAR(f->parameters.at("tau"), 0.2, 0.08) << seed;
    EXPECT_LT(f->gap_val_after_um, 0.9 * f->gap_val_before_um) << seed;
    EXPECT_LT(r->final_gap_val_um, 0.9 * r->baseline_gap_val_um) << seed;
    EXPECT_GT(RollCorrelationWithTruth(f->term, sim.truth), 0.8) << seed;
  }
}

TEST(DiagnosisRollFamilyTest, NoRollFactorsNoRollFinding) {
  for (uint64_t seed = 43; seed < 43 + kRollFamilySeeds; ++seed) {
    const Simulation sim = SimulatedRollMill(seed, 0.0);
    StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_EQ(RollWearFinding(*r), nullptr) << seed << ": " << simulator_test::DescribeReport(*r);
  }
}

// Rolls bought from a new supplier from day 45 on wear faster, with
// unchanged labels: the wear rate steps in calendar time, and rolls that
// served mostly before or after the step look like rolls of their own
// resistance. The diagnosis must not name roll scatter for it.
TEST(DiagnosisRollFamilyTest, ACalendarStepIsNotNamedAsRollScatter) {
  const Simulation sim = SimulatedRollMill(46, 0.0, {"supplier_change"});
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(RollWearFinding(*r), nullptr) << simulator_test::DescribeReport(*r);
}

// The adopted term, refitted as `calibrate --terms` does and applied coil
// by coil by the predictor, predicts as the diagnosis's model does: a roll
// the term knows by its id wears by its multiplier, an unknown roll as its
// type.
TEST(DiagnosisRollFamilyTest,
     TheRollTermMeansTheSameInTheRefitAndThePredictor) {
  const Simulation sim = SimulatedRollMill(41, 0.2);
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok());
  ASSERT_NE(RollWearFinding(*r), nullptr) << simulator_test::DescribeReport(*r);
  std::vector<int> train;
  for (int c = 0; c < static_cast<int>(sim.data.campaigns.size()); c += 3) {
    train.push_back(c);
    if (c + 1 < static_cast<int>(sim.data.campaigns.size()))
      train.push_back(c + 1);
  }
  StatusOr<WearModel> refit =
      RefitWithTerms(sim.data, WearLaw::kWang, r->adopted_model.terms, train);
  ASSERT_TRUE(refit.ok()) << refit.status().ToString();
  const ModelTerm* roll = nullptr;
  for (const ModelTerm& t : refit->terms) {
    if (t.form == TermForm::kRollEffect) roll = &t;
  }
  ASSERT_NE(roll, nullptr);
  EXPECT_GT(RollCorrelationWithTruth(*roll, sim.truth), 0.8);

  // Coil by coil: the same passes on a known roll and on an unknown one
  // differ by exactly that roll's multiplier.
  const Dataset& d = sim.data;
  const Mount& m = d.mounts.front();
  int level = -1;
  for (int l = 0; l < roll->num_levels; ++l) {
    if (roll->levels[l] == m.roll_id) level = l;
  }
  ASSERT_GE(level, 0);
  RollWearState known = MountedRollState(*refit, d, m.campaign, 0);
  RollWearState unknown = known;
  unknown.roll_id = "never-seen";
  PassInput pass;
  pass.force_kn = 15000;
  pass.width_mm = 1200;
  pass.length_m = 800;
  pass.entry_thickness_mm = 4;
  pass.exit_thickness_mm = 3;
  pass.grade = d.grades.front();
  const double a = AddPass(*refit, pass, &known);
  const double b = AddPass(*refit, pass, &unknown);
  ASSERT_GT(b, 0);
  EXPECT_NEAR(a / b, std::exp(roll->params[level]), 1e-9);
}

}  // namespace
}  // namespace rollwear
