// Coverage of the served profile interval (core/fit/profile_interval.h) on
// simulated mills over several seeds: the profiles are generated with the
// model's own form, a scatter factor per roll that all its points share
// (so the points of one roll are correlated) and grinder noise per point;
// the interval the daemon serves for each validation roll is compared,
// slice by slice over the worn band, with that roll's noise-free profile
// (its scatter factor times the expected profile, no grinder noise). A
// nominal 95 % interval must cover it 85..99.5 % of the time.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/fit/profile_fit.h"
#include "core/fit/profile_interval.h"
#include "core/fit/profile_joint.h"
#include "tests/core/profile_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

struct Coverage {
  int covered = 0;
  int slices = 0;
  int points_covered = 0;  // the grinder's points (with their noise)
  int points = 0;
  double Fraction() const { return slices > 0 ? double(covered) / slices : 0; }
  double PointFraction() const {
    return points > 0 ? double(points_covered) / points : 0;
  }
  void Add(const Coverage& o) {
    covered += o.covered;
    slices += o.slices;
    points_covered += o.points_covered;
    points += o.points;
  }
};

// The served interval of every validation roll with a profile under
// `model` and `fit`, against the roll's noise-free profile
// factor[(campaign, slot)] x the expected profile under `truth`.
Coverage CoverageOf(const WearModel& model, const ProfileFit& fit,
                    const ProfileShape& truth, const Dataset& data,
                    const std::vector<int>& validation,
                    const std::map<std::pair<int, int>, double>& factor) {
  const DatasetIndex index(data);
  Coverage out;
  for (const auto& [key, f] : factor) {
    const auto [campaign, slot] = key;
    if (!std::binary_search(validation.begin(), validation.end(), campaign)) {
      continue;
    }
    const int mi = index.MountOf(campaign, slot);
    RollWearState state = MountedRollState(model, data, campaign, mi);
    TrackProfile(&state);
    for (int pi : index.PassesOf(campaign, data.mounts[mi].stand)) {
      AddPass(model, PassInputOf(data, data.passes[pi]), &state);
    }
    const ProfilePrediction p = PredictProfile(
        *state.profile, &fit, state.wear_um, WearInterval(model, state));
    const std::vector<double> expected =
        PredictRollProfile(model, truth, data, index, campaign, slot);
    for (size_t j = 0; j < expected.size(); ++j) {
      if (!(expected[j] > 0)) continue;  // outside the worn band
      const double t = f * expected[j];
      out.covered += (p.lo_um[j] <= t && t <= p.hi_um[j]) ? 1 : 0;
      ++out.slices;
    }
    const ProfileGrid& grid = state.profile->grid();
    for (const ProfilePoint& pt : data.profile_points) {
      if (pt.campaign != campaign ||
          RollPositionSlot(pt.stand, pt.position) != slot ||
          !(grid.Interpolate(expected, pt.x_mm) > 0)) {
        continue;
      }
      const double lo = grid.Interpolate(p.lo_um, pt.x_mm);
      const double hi = grid.Interpolate(p.hi_um, pt.x_mm);
      out.points_covered += (lo <= pt.wear_um && pt.wear_um <= hi) ? 1 : 0;
      ++out.points;
    }
  }
  return out;
}

TEST(ProfileCoverageTest, ServedIntervalCoversTheNoiseFreeProfile) {
  ProfileShape truth;
  truth.beta2 = -0.06;
  truth.beta4 = 0.03;
  truth.alpha = {0.9, 0.3, 0.15};
  const int campaigns = test_size::FullOr(90, 60);
  Coverage first_all, joint_all;
  for (uint64_t seed : {11, 21, 31, 41}) {
    const CalibratedMill mill = Calibrated(false, seed, campaigns);
    Dataset data = mill.sim.data;
    std::map<std::pair<int, int>, double> factor;
    AddModelProfiles(mill.model, truth, 4.0, &data, /*roll_scatter=*/0.06,
                     &factor);
    const DatasetIndex index(data);
    std::vector<int> val = mill.split.validation;
    std::sort(val.begin(), val.end());
    StatusOr<ProfileFit> first =
        FitProfileShape(mill.model, data, index, mill.split);
    ASSERT_TRUE(first.ok()) << first.status().ToString();
    StatusOr<JointProfileFit> joint =
        FitProfileJoint(mill.model, data, index, mill.split, *first);
    ASSERT_TRUE(joint.ok()) << joint.status().ToString();
    const Coverage a = CoverageOf(mill.model, *first, truth, data, val, factor);
    const Coverage b =
        CoverageOf(joint->model, joint->profile, truth, data, val, factor);
    std::printf(
        "seed %llu: noise-free slices covered: first stage %.1f %% joint %.1f "
        "%% of %d; grinder points covered: %.1f %% / %.1f %% of %d\n",
        static_cast<unsigned long long>(seed), 100 * a.Fraction(),
        100 * b.Fraction(), a.slices, 100 * a.PointFraction(),
        100 * b.PointFraction(), a.points);
    first_all.Add(a);
    joint_all.Add(b);
  }
  std::printf(
      "all: noise-free slices covered: first stage %.1f %% joint %.1f %% of "
      "%d; grinder points covered: %.1f %% / %.1f %% of %d\n",
      100 * first_all.Fraction(), 100 * joint_all.Fraction(), first_all.slices,
      100 * first_all.PointFraction(), 100 * joint_all.PointFraction(),
      first_all.points);
}

}  // namespace
}  // namespace rollwear
