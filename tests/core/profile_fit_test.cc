// The first stage of the profile calibration (core/fit/profile_fit.h): the
// shape of g fitted by linear least squares with K from the centre fit.
// (a) Profiles generated with the model's own form, exact K and Gaussian
// noise per point: the five coefficients come back within 3 standard
// errors. (b) The simulator's profiles (its own exponential edge form):
// the validation profile gap against the truth's noise floor, edge and
// body. (c) No profile points: an error, not a fit.
#include "core/fit/profile_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/pass_input.h"
#include "core/fit/study.h"
#include "core/model/aggregation.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "core/sim/simulator.h"
#include "tests/core/profile_test_util.h"

namespace rollwear {
namespace {

TEST(ProfileFitTest, RecoversTheModelsOwnShapeWithinThreeStandardErrors) {
  const CalibratedMill& mill = WithoutProfiles();
  Dataset data = mill.sim.data;
  ProfileShape truth;
  truth.beta2 = -0.06;
  truth.beta4 = 0.03;
  truth.alpha = {0.9, 0.3, 0.15};
  AddModelProfiles(mill.model, truth, 4.0, &data);
  const DatasetIndex index(data);
  StatusOr<ProfileFit> fit =
      FitProfileShape(mill.model, data, index, mill.split);
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  const auto want = ProfileShapeValues(truth);
  const auto got = ProfileShapeValues(fit->shape);
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    const double se = fit->std_error[i];
    std::printf("%-7s true %8.4f fitted %8.4f se %.4f z %+.2f\n",
                ProfileShapeNames()[i].c_str(), want[i], got[i], se,
                (got[i] - want[i]) / se);
    ASSERT_TRUE(std::isfinite(se) && se > 0);
    EXPECT_LT(se, 0.05) << ProfileShapeNames()[i] << " must be well determined";
    EXPECT_NEAR(got[i], want[i], 3 * se) << ProfileShapeNames()[i];
  }
  // The residual sd is the generator's noise, and the gap its mean |.|
  // (sqrt(2/pi) sd = 3.19 µm), on training and validation alike.
  EXPECT_NEAR(fit->residual_sd_um, 4.0, 0.1);
  EXPECT_NEAR(fit->train.gap_um, 4.0 * std::sqrt(2 / M_PI), 0.1);
  EXPECT_NEAR(fit->validation.gap_um, 4.0 * std::sqrt(2 / M_PI), 0.15);
  EXPECT_GT(fit->train.n_edge, 0);
  EXPECT_GT(fit->train.n_body, fit->train.n_edge);
  // Only the generator's points > 100 mm beyond the worn band are in
  // neither zone.
  EXPECT_LE(fit->train.n_edge + fit->train.n_body, fit->train.n_points);
  EXPECT_GT(fit->train.n_edge + fit->train.n_body, 0.99 * fit->train.n_points);
  EXPECT_EQ(fit->train.n_profiles + fit->validation.n_profiles,
            static_cast<int>(data.measurements.size()));
}

// The truth's noise floor of the validation points by zone: mean
// |measured - noise-free|, the noise-free profile recomputed from the true
// K (option 1) and the truth's own edge form 1 + beta2 (u/b)^2 +
// A (exp(-d/lambda) - exp(-b/lambda)), zones as profile_fit.h defines them.
struct ZoneFloor {
  double all = 0, edge = 0, body = 0;
};
ZoneFloor ValidationFloor(const Simulation& sim, const CampaignSplit& split) {
  const Dataset& d = sim.data;
  const SimulationTruth& t = sim.truth;
  const SimulatedProfileShape& s = t.profile_shape;
  const DatasetIndex index(d);
  double sum[3] = {0, 0, 0};
  int n[3] = {0, 0, 0};
  for (const ProfilePoint& p : d.profile_points) {
    if (!std::binary_search(split.validation.begin(), split.validation.end(),
                            p.campaign)) {
      continue;
    }
    const Mount& m = d.mounts[index.MountOf(
        p.campaign, RollPositionSlot(p.stand, p.position))];
    const double kfr = t.k_position.at(RollPositionName(m.stand, m.position)) *
                       t.k_roll_type.at(d.roll_types[m.roll_type]);
    double w = 0, lo = 1e9, hi = -1e9;
    for (int pi : index.PassesOf(p.campaign, p.stand)) {
      const Pass& pass = d.passes[pi];
      const double c =
          StripCentreMm(p.position == Position::kTop, pass.shift_mm);
      const double b = pass.width_mm / 2;
      lo = std::min(lo, c - b);
      hi = std::max(hi, c + b);
      const double u = p.x_mm - c, dist = b - std::abs(u);
      if (dist < 0) continue;
      const double g = 1 + s.body_beta2 * (u / b) * (u / b) +
                       s.edge_amplitude * (std::exp(-dist / s.edge_decay_mm) -
                                           std::exp(-b / s.edge_decay_mm));
      w += kfr * t.k_grade.at(d.grades[pass.grade]) *
           BaseLoad(WearLaw::kWang, MakeLoadInput(pass, m)) * g;
    }
    const double e = std::abs(p.wear_um - w);
    const double to_end =
        std::min(std::abs(p.x_mm - lo), std::abs(p.x_mm - hi));
    const int zone = to_end <= 100 ? 1 : (p.x_mm > lo && p.x_mm < hi ? 2 : -1);
    sum[0] += e;
    ++n[0];
    if (zone > 0) {
      sum[zone] += e;
      ++n[zone];
    }
  }
  return {sum[0] / n[0], sum[1] / n[1], sum[2] / n[2]};
}

// On the simulator's profiles (an exponential edge rise the ramps only
// approximate, roll scatter shared by a profile's points) the validation
// gap is compared with the truth's noise floor: mean |measured - noise-free|.
TEST(ProfileFitTest, SimulatedValidationGapNearTheProfileNoiseFloor) {
  const CalibratedMill& mill = WithProfiles();
  ASSERT_TRUE(mill.sim.truth.has_profiles);
  const Dataset& data = mill.sim.data;
  const DatasetIndex index(data);
  StatusOr<ProfileFit> fit =
      FitProfileShape(mill.model, data, index, mill.split);
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  const double floor = mill.sim.truth.profile_noise_floor_um;
  const SimulatedProfileShape& t = mill.sim.truth.profile_shape;
  std::printf("truth: beta2 %.4f, edge A %.3f lambda %.1f mm; floor %.2f µm\n",
              t.body_beta2, t.edge_amplitude, t.edge_decay_mm, floor);
  const auto got = ProfileShapeValues(fit->shape);
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    std::printf("%-7s fitted %8.4f se %.4f\n", ProfileShapeNames()[i].c_str(),
                got[i], fit->std_error[i]);
  }
  for (const ProfileGap* g : {&fit->train, &fit->validation}) {
    std::printf(
        "%s: %d profiles, %d points, gap %.2f µm; edge %d pts %.2f µm,"
        " body %d pts %.2f µm\n",
        g == &fit->train ? "train" : "val", g->n_profiles, g->n_points,
        g->gap_um, g->n_edge, g->edge_um, g->n_body, g->body_um);
  }
  const ZoneFloor val_floor = ValidationFloor(mill.sim, mill.split);
  std::printf("validation floor: all %.2f µm, edge %.2f µm, body %.2f µm\n",
              val_floor.all, val_floor.edge, val_floor.body);
  EXPECT_GT(fit->validation.n_points, 1000);
  EXPECT_LT(fit->validation.gap_um, 1.10 * floor);
  // Against the same points' own floor, zone by zone, the 5 %: the
  // ramps' misfit of the exponential edge does not show at this noise.
  EXPECT_LT(fit->validation.gap_um, 1.05 * val_floor.all);
  EXPECT_LT(fit->validation.edge_um, 1.05 * val_floor.edge);
  EXPECT_LT(fit->validation.body_um, 1.05 * val_floor.body);
  EXPECT_GT(fit->validation.gap_um, val_floor.all) << "below the noise?";
}

// Points only over the middle of the barrel, away from every strip edge:
// the edge ramps are 0 there and the shape is not identified.
TEST(ProfileFitTest, ProfilesWithoutTheEdgesDoNotIdentifyTheShape) {
  const CalibratedMill& mill = WithoutProfiles();
  Dataset data = mill.sim.data;
  AddModelProfiles(mill.model, ProfileShape{}, 4.0, &data);
  std::erase_if(data.profile_points,
                [](const ProfilePoint& p) { return std::abs(p.x_mm) > 200; });
  ASSERT_GT(data.profile_points.size(), 1000u);
  const DatasetIndex index(data);
  StatusOr<ProfileFit> fit =
      FitProfileShape(mill.model, data, index, mill.split);
  ASSERT_FALSE(fit.ok());
  EXPECT_EQ(fit.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(fit.status().message().find("do not identify the shape"),
            std::string::npos)
      << fit.status().message();
}

TEST(ProfileFitTest, WithoutProfilePointsThereIsNoFit) {
  const CalibratedMill& mill = WithoutProfiles();
  ASSERT_TRUE(mill.sim.data.profile_points.empty());
  const DatasetIndex index(mill.sim.data);
  StatusOr<ProfileFit> fit =
      FitProfileShape(mill.model, mill.sim.data, index, mill.split);
  ASSERT_FALSE(fit.ok());
  EXPECT_EQ(fit.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(fit.status().message().find("0 profile points"), std::string::npos)
      << fit.status().message();
}

}  // namespace
}  // namespace rollwear
