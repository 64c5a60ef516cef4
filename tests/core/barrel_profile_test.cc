// The barrel profile's slicing model (core/model/barrel_profile.h): the
// grid, the distribution across the strip, the per-pass update against the
// sufficient statistics, and box wear smeared by shifting.
#include "core/model/barrel_profile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace rollwear {
namespace {

TEST(BarrelProfileTest, GridIsSymmetricWithTheCentreAsASlice) {
  const ProfileGrid grid;
  EXPECT_EQ(grid.slices(), 201);
  EXPECT_DOUBLE_EQ(grid.x(0), -1000);
  EXPECT_DOUBLE_EQ(grid.x(100), 0);
  EXPECT_DOUBLE_EQ(grid.x(200), 1000);
  std::vector<double> v(201);
  for (int j = 0; j < 201; ++j) v[j] = grid.x(j) * 2 + 7;
  EXPECT_NEAR(grid.Interpolate(v, 123.4), 123.4 * 2 + 7, 1e-9);
  EXPECT_DOUBLE_EQ(grid.Interpolate(v, -5000), v.front());
}

TEST(BarrelProfileTest, WithoutShapeEverySliceUnderTheStripWearsTheCentreWear) {
  const ProfileGrid grid;
  std::vector<double> profile(grid.slices(), 0.0);
  // Top roll, shift +60 mm: strip centreline at x = -60, 1200 mm wide.
  const double c = StripCentreMm(true, 60);
  EXPECT_DOUBLE_EQ(c, -60);
  EXPECT_DOUBLE_EQ(StripCentreMm(false, 60), 60);
  AddPassProfile(grid, ProfileShape{}, 3.5, c, 600, &profile);
  for (int j = 0; j < grid.slices(); ++j) {
    const bool covered = std::abs(grid.x(j) - c) <= 600;
    EXPECT_DOUBLE_EQ(profile[j], covered ? 3.5 : 0.0) << "x = " << grid.x(j);
  }
  EXPECT_DOUBLE_EQ(profile[100], 3.5);  // the centre: today's centre wear
}

TEST(BarrelProfileTest, EdgeRampsRiseTowardsTheStripEdgeAndLeaveTheCentre) {
  ProfileShape shape;
  shape.alpha = {0.5, 0.2, 0.1};
  shape.beta2 = -0.1;
  const double b = 625;
  // At the centre the ramps are 0 and the body terms vanish.
  EXPECT_DOUBLE_EQ(Distribution(shape, 0, b), 1.0);
  // 5 mm inside the edge: 1 - 0.1 + 0.5 (1 - 5/15)^2 + 0.2 (1 - 5/40)^2
  // + 0.1 (1 - 5/100)^2.
  const double u = b - 5;
  const double expected = 1 - 0.1 * (u / b) * (u / b) +
                          0.5 * std::pow(1 - 5.0 / 15, 2) +
                          0.2 * std::pow(1 - 5.0 / 40, 2) +
                          0.1 * std::pow(1 - 5.0 / 100, 2);
  EXPECT_NEAR(Distribution(shape, u, b), expected, 1e-12);
  EXPECT_NEAR(Distribution(shape, -u, b), expected, 1e-12);
  EXPECT_DOUBLE_EQ(Distribution(shape, b + 0.1, b), 0.0);
  // Without the (falling) body term, a monotone rise over the last 100 mm.
  shape.beta2 = 0;
  double last = Distribution(shape, b - 100, b);
  EXPECT_DOUBLE_EQ(last, 1.0);
  for (double d = 95; d >= 0; d -= 5) {
    const double g = Distribution(shape, b - d, b);
    EXPECT_GT(g, last) << "d = " << d;
    last = g;
  }
}

TEST(BarrelProfileTest, SufficientStatisticsEqualThePassByPassUpdate) {
  const ProfileGrid grid;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> width(800, 1600), shift(-150, 150),
      wear(0.5, 4);
  ProfileShape shape;
  shape.beta2 = 0.08;
  shape.beta4 = -0.03;
  shape.alpha = {0.6, 0.25, 0.1};
  ProfileStats stats(grid);
  std::vector<double> direct(grid.slices(), 0.0);
  for (int p = 0; p < 500; ++p) {
    const bool top = p % 2 == 0;
    const double c = StripCentreMm(top, shift(rng));
    const double b = width(rng) / 2;
    const double w = wear(rng);
    stats.AddPass(w, c, b);
    AddPassProfile(grid, shape, w, c, b, &direct);
  }
  const std::vector<double> batch = stats.Evaluate(shape);
  double max_rel = 0;
  for (int j = 0; j < grid.slices(); ++j) {
    if (direct[j] == 0) {
      EXPECT_EQ(batch[j], 0.0);
      continue;
    }
    max_rel = std::max(max_rel, std::abs(batch[j] - direct[j]) / direct[j]);
  }
  EXPECT_LT(max_rel, 1e-12);
  // The derivative with respect to a coefficient is that statistic.
  ProfileShape bumped = shape;
  bumped.alpha[1] += 1e-3;
  const std::vector<double> moved = stats.Evaluate(bumped);
  for (int j = 0; j < grid.slices(); j += 10) {
    EXPECT_NEAR((moved[j] - batch[j]) / 1e-3, stats.slice(j)[4],
                1e-6 * (1 + stats.slice(j)[4]));
  }
}

// ProfileStats::At reads the six sums between slices as Interpolate reads
// a profile: the profile of any shape at x is coefficients . At(x).
TEST(BarrelProfileTest, SumsBetweenSlicesInterpolateLikeTheProfile) {
  const ProfileGrid grid;
  ProfileShape shape;
  shape.beta2 = -0.05;
  shape.beta4 = 0.02;
  shape.alpha = {0.7, 0.2, 0.1};
  ProfileStats stats(grid);
  stats.AddPass(2.0, -37, 610);
  stats.AddPass(1.5, 52, 455);
  const std::vector<double> profile = stats.Evaluate(shape);
  const auto coef = shape.Coefficients();
  for (double x : {-647.0, -606.3, -400.5, 0.0, 3.7, 480.0, 504.9, 2000.0}) {
    const auto sums = stats.At(x);
    double w = 0;
    for (int i = 0; i < kProfileBasis; ++i) w += coef[i] * sums[i];
    EXPECT_NEAR(w, grid.Interpolate(profile, x), 1e-12) << "x = " << x;
  }
  // At a slice centre: that slice's sums, exactly; 5 mm on: the mean of
  // the two neighbours.
  EXPECT_EQ(stats.At(-400)[3], stats.slice(60)[3]);
  EXPECT_DOUBLE_EQ(stats.At(-595)[5],
                   (stats.slice(40)[5] + stats.slice(41)[5]) / 2);
  // (a real mean: the 100 mm ramp falls inwards from the edge at -647)
  EXPECT_GT(stats.slice(40)[5], stats.slice(41)[5] + 0.1);
}

// Box wear: a campaign of one width wears a flat body with peaks at the
// strip edges; a shifting cycle spreads the same wear over a wider band and
// the peaks smear out (the reason mills shift work rolls).
TEST(BarrelProfileTest, ShiftingSmearsTheEdgePeaksOfBoxWear) {
  const ProfileGrid grid;
  ProfileShape shape;
  shape.alpha = {0.8, 0.3, 0};
  const int kPasses = 200;
  auto campaign = [&](double amplitude_mm) {
    std::vector<double> profile(grid.slices(), 0.0);
    for (int p = 0; p < kPasses; ++p) {
      // Triangular shifting cycle of 20 passes between +-amplitude.
      const double phase = (p % 20) / 20.0;
      const double s =
          amplitude_mm * (phase < 0.5 ? 4 * phase - 1 : 3 - 4 * phase);
      AddPassProfile(grid, shape, 1.0, StripCentreMm(true, s), 625, &profile);
    }
    return profile;
  };
  const std::vector<double> fixed = campaign(0);
  const std::vector<double> shifted = campaign(100);
  const double body = fixed[100];  // centre: kPasses * 1.0
  EXPECT_DOUBLE_EQ(body, kPasses);
  const double peak_fixed = *std::max_element(fixed.begin(), fixed.end());
  const double peak_shifted = *std::max_element(shifted.begin(), shifted.end());
  // Without shifting the peak stands 1 + 0.8 (1-5/15)^2... above the body
  // at the slice 5 mm from the edge: about 70 % higher.
  EXPECT_GT(peak_fixed / body, 1.5);
  // With +-100 mm shifting the edge excess is spread over ~200 mm: its
  // height falls below a quarter of the unshifted excess.
  EXPECT_LT((peak_shifted - body) / (peak_fixed - body), 0.25);
  // ... and the worn band widens by the shift amplitude on each side.
  auto worn_width = [&](const std::vector<double>& v) {
    int n = 0;
    for (double w : v) n += w > 0;
    return n * grid.slice_mm;
  };
  EXPECT_NEAR(worn_width(shifted) - worn_width(fixed), 200, 2 * grid.slice_mm);
}

}  // namespace
}  // namespace rollwear
