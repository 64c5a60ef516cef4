// The one-way ANOVA intraclass correlation (core/base/intraclass.h) against
// clusters drawn with a known shared component: rho = s_a^2 / (s_a^2 +
// s_e^2) within its sampling error, 0 (clamped) without one, the corrected
// mean cluster size for unequal clusters, and 0.99 for a single cluster.
#include "core/base/intraclass.h"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/random.h"

namespace rollwear {
namespace {

// `clusters` clusters of `size` values a_c + e_ci, a_c ~ N(0, sa), e ~ N(0,
// se).
void Draw(uint64_t seed, int clusters, int size, double sa, double se,
          std::vector<double>* values, std::vector<int>* cluster) {
  Random rng(seed);
  for (int c = 0; c < clusters; ++c) {
    const double a = rng.Normal(0, sa);
    for (int i = 0; i < size; ++i) {
      values->push_back(a + rng.Normal(0, se));
      cluster->push_back(c);
    }
  }
}

TEST(IntraclassTest, RecoversTheSharedShareOfTheVariance) {
  // rho = 0.09 / (0.09 + 0.16) = 0.36; with 2000 clusters of 6 its
  // standard error is about 0.012.
  std::vector<double> v;
  std::vector<int> c;
  Draw(7, 2000, 6, 0.3, 0.4, &v, &c);
  const Intraclass icc = OneWayIntraclass(v, c);
  EXPECT_NEAR(icc.rho, 0.36, 0.04);
  EXPECT_NEAR(icc.n0, 6.0, 1e-9);
  EXPECT_NEAR(icc.variance, 0.25, 0.015);
}

TEST(IntraclassTest, NoSharedComponentGivesNearZero) {
  std::vector<double> v;
  std::vector<int> c;
  Draw(8, 2000, 6, 0.0, 1.0, &v, &c);
  EXPECT_LT(OneWayIntraclass(v, c).rho, 0.03);
}

TEST(IntraclassTest, UnequalClustersUseTheCorrectedMeanSize) {
  // Sizes 2 and 4: n0 = (6 - (4 + 16) / 6) / 1 = 8 / 3.
  const std::vector<double> v = {1, 2, 5, 6, 7, 8};
  const std::vector<int> c = {0, 0, 1, 1, 1, 1};
  const Intraclass icc = OneWayIntraclass(v, c);
  EXPECT_NEAR(icc.n0, 8.0 / 3.0, 1e-12);
  EXPECT_GT(icc.rho, 0.5);  // the cluster means differ by 5, within sd ~1
}

TEST(IntraclassTest, OneClusterCountsAsFullyCorrelated) {
  EXPECT_DOUBLE_EQ(OneWayIntraclass({1, 2, 3}, {4, 4, 4}).rho, 0.99);
  EXPECT_DOUBLE_EQ(OneWayIntraclass({}, {}).rho, 0.0);
}

}  // namespace
}  // namespace rollwear
