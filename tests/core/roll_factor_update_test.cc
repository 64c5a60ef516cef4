// A roll's own factor re-estimated from its readings
// (core/model/roll_factor_update.h): the prior without readings, the
// weighted least-squares multiplier when the prior is weak, intervals that
// cover a simulated mill's factors, and the term's levels set in place.
#include "core/model/roll_factor_update.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace rollwear {
namespace {

TEST(RollFactorUpdateTest, WithoutReadingsARollIsAtItsTypesValue) {
  const RollFactorPosterior p = RollFactorPosteriorOf(0.2, {10, 0.05}, {});
  EXPECT_EQ(p.log_factor, 0);
  EXPECT_EQ(p.log_sd, 0.2);
  EXPECT_EQ(p.readings, 0);
  // A reading without a positive prediction tells nothing, nor does any
  // reading under a model without a noise model.
  const RollFactorPosterior q =
      RollFactorPosteriorOf(0.2, {10, 0.05}, {{0, 0, 50}});
  EXPECT_EQ(q.readings, 0);
  EXPECT_EQ(q.log_factor, 0);
  const RollFactorPosterior n =
      RollFactorPosteriorOf(0.2, {0, 0}, {{100, 0, 50}});
  EXPECT_EQ(n.log_factor, 0);
  EXPECT_EQ(n.log_sd, 0.2);
}

// With a prior too weak to matter and a constant noise the mode is the
// least-squares multiplier sum x (y - o) / sum x^2 (the minimum does not
// depend on writing m = e^b).
TEST(RollFactorUpdateTest, AWeakPriorGivesTheLeastSquaresMultiplier) {
  const std::vector<RollReading> r = {
      {120, 5, 160}, {300, -3, 410}, {80, 0, 70}};
  double sxy = 0, sxx = 0;
  for (const RollReading& x : r) {
    sxy += x.base_um * (x.measured_um - x.offset_um);
    sxx += x.base_um * x.base_um;
  }
  const RollFactorPosterior p = RollFactorPosteriorOf(1e4, {15, 0}, r);
  EXPECT_EQ(p.readings, 3);
  EXPECT_NEAR(std::exp(p.log_factor), sxy / sxx, 1e-9);
  // The Laplace sd: 1 / sqrt(sum (x e^b)^2 / s^2) (the prior adds 1e-8).
  EXPECT_NEAR(p.log_sd, 15 / std::sqrt(sxx * std::exp(2 * p.log_factor)), 1e-6);
}

// The noise grows with the wear, so the weights are those of the roll's
// own wear: the same readings give the same factor whatever factor their
// predictions were made with (the daemon re-estimates from any state).
TEST(RollFactorUpdateTest, TheFactorDependsOnTheReadingsOnly) {
  const std::vector<RollReading> r = {
      {120, 5, 190}, {300, -3, 450}, {80, 0, 95}};
  const RollFactorPosterior p = RollFactorPosteriorOf(0.2, {12, 0.08}, r);
  // At the mode the gradient of F (header) is zero with the weights at
  // the mode.
  const double m = std::exp(p.log_factor);
  double g = p.log_factor / (0.2 * 0.2);
  for (const RollReading& x : r) {
    const double j = x.base_um * m;
    g -= j * (x.measured_um - x.offset_um - j) / (144 + 0.0064 * j * j);
  }
  EXPECT_NEAR(g, 0, 1e-9);
  EXPECT_GT(m, 1.2);
  EXPECT_LT(m, 1.6);
}

// A mill of 300 rolls with factors exp(b), b ~ N(0, 0.2^2), each measured
// 1-8 times with the noise the model states: the 95 % intervals cover
// 90-99 % of the true factors, and the estimates are far closer to the
// truth than the prior's spread.
TEST(RollFactorUpdateTest, IntervalsCoverASimulatedMillsFactors) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0, 1);
  std::uniform_real_distribution<double> wear(60, 450);
  std::uniform_int_distribution<int> count(1, 8);
  const double tau = 0.2;
  int covered = 0, rolls = 300;
  double sq = 0;
  for (int k = 0; k < rolls; ++k) {
    const double b = tau * normal(rng);
    std::vector<RollReading> readings(count(rng));
    for (RollReading& r : readings) {
      r.base_um = wear(rng);
      r.offset_um = 10 * normal(rng);
      const double truth = r.base_um * std::exp(b);
      r.measured_um =
          truth + r.offset_um + std::hypot(12.0, 0.06 * truth) * normal(rng);
    }
    const RollFactorPosterior p =
        RollFactorPosteriorOf(tau, {12, 0.06}, readings);
    covered += std::abs(p.log_factor - b) <= 1.959964 * p.log_sd ? 1 : 0;
    sq += (p.log_factor - b) * (p.log_factor - b);
    EXPECT_LT(p.log_sd, tau);
  }
  const double coverage = static_cast<double>(covered) / rolls;
  EXPECT_GE(coverage, 0.90);
  EXPECT_LE(coverage, 0.99);
  EXPECT_LT(std::sqrt(sq / rolls), 0.5 * tau);
}

TEST(RollFactorUpdateTest, SetRollLevelUpdatesOrAddsTheRoll) {
  ModelTerm t;
  t.form = TermForm::kRollEffect;
  t.covariate = "roll_id";
  t.scale = 0.15;
  t.levels = {"A", "B"};
  t.params = {0.1, -0.2};
  t.num_levels = 2;
  SetRollLevel("B", {0.05, 0.04, 3}, &t);
  SetRollLevel("C", {0.3, 0.1, 1}, &t);
  ASSERT_EQ(t.num_levels, 3);
  ASSERT_EQ(t.params.size(), 3u);
  EXPECT_EQ(t.params[1], 0.05);
  EXPECT_EQ(t.level_sd[1], 0.04);
  EXPECT_EQ(t.level_readings[1], 3);
  // A level stored without its sd takes the prior's.
  EXPECT_EQ(t.level_sd[0], 0.15);
  EXPECT_EQ(t.levels[2], "C");
  EXPECT_EQ(RollLogFactor(t, "C"), 0.3);
  EXPECT_EQ(RollLogFactor(t, "unknown"), 0);
  const std::optional<RollWearFactor> f = RollWearFactorOf({t}, "C");
  ASSERT_TRUE(f.has_value());
  EXPECT_NEAR(f->value, std::exp(0.3), 1e-12);
  EXPECT_EQ(f->readings, 1);
  EXPECT_TRUE(f->known);
}

}  // namespace
}  // namespace rollwear
