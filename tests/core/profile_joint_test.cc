// The joint Levenberg-Marquardt fit of K and the profile shape
// (core/fit/profile_joint.h). (a) Profiles generated with the model's own
// form, a shared scatter per roll and point noise: the shape comes back
// within 3 standard errors, the weighting finds the intra-roll correlation,
// and the centre gap is not worse than the centre fit's. (b) The
// simulator's profiles (its own exponential edge form): the joint fit's
// validation profile gap within 5 % of the noise floor, and no worse than
// the first stage's; the centre gap not worse than today's.
#include "core/fit/profile_joint.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/fit/profile_fit.h"
#include "tests/core/profile_test_util.h"

namespace rollwear {
namespace {

double CentreGap(const WearModel& model, const Dataset& data,
                 const std::vector<int>& campaigns) {
  const DatasetIndex index(data);
  double sum = 0;
  int n = 0;
  for (const MeasuredPrediction& m :
       PredictMeasured(model, data, index, campaigns)) {
    sum += std::abs(m.measured_um - m.expected_um);
    ++n;
  }
  return sum / n;
}

void Print(const char* name, const ProfileFit& fit) {
  const auto got = ProfileShapeValues(fit.shape);
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    std::printf("%s %-7s %8.4f se %.4f\n", name, ProfileShapeNames()[i].c_str(),
                got[i], fit.std_error[i]);
  }
  std::printf("%s gap train %.2f val %.2f (edge %.2f body %.2f) µm\n", name,
              fit.train.gap_um, fit.validation.gap_um, fit.validation.edge_um,
              fit.validation.body_um);
}

TEST(ProfileJointTest, RecoversTheShapeWithSharedRollScatter) {
  const CalibratedMill& mill = WithoutProfiles();
  Dataset data = mill.sim.data;
  ProfileShape truth;
  truth.beta2 = -0.06;
  truth.beta4 = 0.03;
  truth.alpha = {0.9, 0.3, 0.15};
  AddModelProfiles(mill.model, truth, 4.0, &data, /*roll_scatter=*/0.04);
  const DatasetIndex index(data);
  StatusOr<ProfileFit> first =
      FitProfileShape(mill.model, data, index, mill.split);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  StatusOr<JointProfileFit> joint =
      FitProfileJoint(mill.model, data, index, mill.split, *first);
  ASSERT_TRUE(joint.ok()) << joint.status().ToString();
  Print("first", *first);
  Print("joint", joint->profile);
  std::printf("rho %.3f, %d iterations, converged %d\n",
              joint->intra_roll_correlation, joint->iterations,
              joint->converged);
  EXPECT_TRUE(joint->converged);
  EXPECT_TRUE(joint->at_bound.empty());
  // A 4 % roll scatter on profiles of ~100 µm against 4 µm point noise:
  // most of a profile's residual variance is shared by its points.
  EXPECT_GT(joint->intra_roll_correlation, 0.2);
  EXPECT_LT(joint->intra_roll_correlation, 0.95);
  const auto want = ProfileShapeValues(truth);
  const auto got = ProfileShapeValues(joint->profile.shape);
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    const double se = joint->profile.std_error[i];
    ASSERT_TRUE(std::isfinite(se) && se > 0) << ProfileShapeNames()[i];
    EXPECT_LT(se, 0.1) << ProfileShapeNames()[i];
    EXPECT_NEAR(got[i], want[i], 3 * se) << ProfileShapeNames()[i];
  }
  // K hardly moves (the profiles were made with the centre fit's K), and
  // the centre readings are predicted as well as by the centre fit.
  const double before = CentreGap(mill.model, data, mill.split.validation);
  EXPECT_NEAR(joint->centre_gap_val_um, before, 0.02 * before);
  // Here the profiles were made with the centre fit's K while the centre
  // readings are the simulator's own: the first stage holds the profiles'
  // exact K, the joint fit a compromise with the readings (measured: 4 %
  // above on validation; a 5 % bound).
  EXPECT_LE(joint->profile.validation.gap_um,
            1.05 * first->validation.gap_um);
}

TEST(ProfileJointTest, SimulatedProfilesNearTheNoiseFloorAndCentreNoWorse) {
  const CalibratedMill& mill = WithProfiles();
  const Dataset& data = mill.sim.data;
  const DatasetIndex index(data);
  StatusOr<ProfileFit> first =
      FitProfileShape(mill.model, data, index, mill.split);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  StatusOr<JointProfileFit> joint =
      FitProfileJoint(mill.model, data, index, mill.split, *first);
  ASSERT_TRUE(joint.ok()) << joint.status().ToString();
  Print("first", *first);
  Print("joint", joint->profile);
  const double floor = mill.sim.truth.profile_noise_floor_um;
  const double centre_before = CentreGap(mill.model, data, mill.split.validation);
  std::printf("floor %.2f µm; centre gap val %.2f -> %.2f µm; rho %.3f\n",
              floor, centre_before, joint->centre_gap_val_um,
              joint->intra_roll_correlation);
  EXPECT_LT(joint->profile.validation.gap_um, 1.05 * floor);
  EXPECT_LE(joint->profile.validation.gap_um,
            1.01 * first->validation.gap_um);
  EXPECT_LE(joint->centre_gap_val_um, 1.02 * centre_before);
}

TEST(ProfileJointTest, WithoutTrainingProfilesThereIsNoJointFit) {
  const CalibratedMill& mill = WithoutProfiles();
  const DatasetIndex index(mill.sim.data);
  StatusOr<JointProfileFit> joint = FitProfileJoint(
      mill.model, mill.sim.data, index, mill.split, ProfileFit{});
  ASSERT_FALSE(joint.ok());
  EXPECT_EQ(joint.status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace rollwear
