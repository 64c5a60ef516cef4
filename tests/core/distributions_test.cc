// Tail probabilities against tabulated values (Abramowitz & Stegun tables
// 26.7-26.9; R's pchisq/pt/pf give the same digits).
#include "core/base/distributions.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rollwear {
namespace {

TEST(DistributionsTest, ChiSquareMatchesTables) {
  EXPECT_NEAR(ChiSquareSurvival(3.841458820694124, 1), 0.05, 1e-12);
  EXPECT_NEAR(ChiSquareSurvival(5.991464547107979, 2), 0.05, 1e-12);
  EXPECT_NEAR(ChiSquareSurvival(6.634896601021214, 1), 0.01, 1e-12);
  EXPECT_NEAR(ChiSquareSurvival(23.20925117, 10), 0.01, 1e-9);
  EXPECT_NEAR(ChiSquareSurvival(2.0, 2), std::exp(-1.0), 1e-14);  // exp(-x/2)
  EXPECT_DOUBLE_EQ(ChiSquareSurvival(0.0, 3), 1.0);
  EXPECT_LT(ChiSquareSurvival(200.0, 2), 1e-40);
}

TEST(DistributionsTest, StudentTMatchesTables) {
  EXPECT_NEAR(StudentTTwoSided(2.228138851986274, 10), 0.05, 1e-12);
  EXPECT_NEAR(StudentTTwoSided(1.959963984540054, 1e7), 0.05, 1e-6);
  EXPECT_NEAR(StudentTTwoSided(0.0, 5), 1.0, 1e-15);
  EXPECT_NEAR(StudentTTwoSided(-2.228138851986274, 10), 0.05, 1e-12);
}

TEST(DistributionsTest, FMatchesTables) {
  EXPECT_NEAR(FSurvival(3.325834530413011, 5, 10), 0.05, 1e-12);
  EXPECT_NEAR(FSurvival(4.964602743730711, 1, 10), 0.05, 1e-12);
  EXPECT_NEAR(RegularizedBeta(0.5, 2, 2), 0.5, 1e-15);
}

}  // namespace
}  // namespace rollwear
