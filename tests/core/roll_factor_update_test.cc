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

// F(b) of roll_factor_update.h, the weights at the roll type's prediction.
double Objective(double b, double tau, ReadingNoise noise,
                 const std::vector<RollReading>& readings) {
  double f = 0.5 * b * b / (tau * tau);
  for (const RollReading& r : readings) {
    const double s2 = noise.sd_um * noise.sd_um +
                      (noise.rel * r.base_um) * (noise.rel * r.base_um);
    const double e = r.measured_um - r.offset_um - r.base_um * std::exp(b);
    f += 0.5 * e * e / s2;
  }
  return f;
}

// With a prior too weak to matter the mode is the weighted least-squares
// multiplier sum w x (y - o) / sum w x^2 (the minimum does not depend on
// writing m = e^b), w = 1 / (sigma0^2 + (rho x)^2).
TEST(RollFactorUpdateTest, AWeakPriorGivesTheWeightedLeastSquaresMultiplier) {
  const std::vector<RollReading> r = {
      {120, 5, 160}, {300, -3, 410}, {80, 0, 70}};
  const ReadingNoise noise{15, 0.05};
  double sxy = 0, sxx = 0;
  for (const RollReading& x : r) {
    const double w = 1 / (225 + 0.0025 * x.base_um * x.base_um);
    sxy += w * x.base_um * (x.measured_um - x.offset_um);
    sxx += w * x.base_um * x.base_um;
  }
  const RollFactorPosterior p = RollFactorPosteriorOf(1e4, noise, r);
  EXPECT_EQ(p.readings, 3);
  EXPECT_TRUE(p.converged);
  EXPECT_NEAR(std::exp(p.log_factor), sxy / sxx, 1e-7);
  // The Gauss-Newton sd: 1 / sqrt(sum w (x e^b)^2) (the prior adds 1e-8).
  EXPECT_NEAR(p.log_sd, 1 / std::sqrt(sxx * std::exp(2 * p.log_factor)), 1e-6);
}

// F need not be convex: the answer is its global minimum, also where a
// reading lies at or below its offset with no absolute noise (sigma0 = 0),
// or far above its prediction; an impossible reading is not converged.
TEST(RollFactorUpdateTest, TheModeIsTheGlobalMinimumEvenForOddReadings) {
  const struct {
    double tau;
    ReadingNoise noise;
    std::vector<RollReading> readings;
  } cases[] = {
      {0.2, {12, 0.08}, {{120, 5, 190}, {300, -3, 450}, {80, 0, 95}}},
      {0.2, {0, 0.06}, {{100, 0, 0}}},      // a zero reading
      {1.0, {0, 0.06}, {{100, 0, -50}}},    // below its offset
      {1.0, {12, 0.06}, {{100, 0, -50}}},   // the same with sigma0
      {0.1, {12, 0.15}, {{100, 0, 3000}}},  // 30 x its prediction
      {0.3, {10, 0.05}, {{100, 0, 300}, {100, 0, 20}, {50, 10, 400}}},
  };
  for (const auto& c : cases) {
    const RollFactorPosterior p =
        RollFactorPosteriorOf(c.tau, c.noise, c.readings);
    ASSERT_TRUE(p.converged);
    ASSERT_TRUE(std::isfinite(p.log_factor) && std::isfinite(p.log_sd));
    const double at_mode = Objective(p.log_factor, c.tau, c.noise, c.readings);
    for (double b = -6; b <= 6; b += 0.001) {
      ASSERT_LE(at_mode, Objective(b, c.tau, c.noise, c.readings) + 1e-9)
          << "tau " << c.tau << ", b " << b << ", mode " << p.log_factor;
    }
    EXPECT_GT(p.log_sd, 0);
    EXPECT_LE(p.log_sd, c.tau);
  }
  // A zero reading pulls the factor down as far as the prior lets it.
  const RollFactorPosterior zero =
      RollFactorPosteriorOf(0.2, {0, 0.06}, {{100, 0, 0}});
  EXPECT_LT(zero.log_factor, -0.1);
  EXPECT_GT(zero.log_factor, -2.0);  // -1.14: held by the prior
  // 10^7 times the prediction: no roll of this type; not converged.
  EXPECT_FALSE(
      RollFactorPosteriorOf(0.2, {12, 0.06}, {{100, 0, 1e9}}).converged);
  // A prior sd too small to invert is the prior itself.
  const RollFactorPosterior tiny =
      RollFactorPosteriorOf(1e-200, {12, 0.06}, {{100, 0, 150}});
  EXPECT_EQ(tiny.log_factor, 0);
  EXPECT_EQ(tiny.log_sd, 1e-200);
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
