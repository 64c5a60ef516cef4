// Shared by the profile calibration tests (profile_fit_test.cc,
// profile_joint_test.cc): a simulated mill calibrated at the centre, and
// profiles generated with the model's own form.
//
// Thread-safety: the mills are built once, on first use, and then only read.
#ifndef ROLLWEAR_TESTS_CORE_PROFILE_TEST_UTIL_H_
#define ROLLWEAR_TESTS_CORE_PROFILE_TEST_UTIL_H_

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/pass_input.h"
#include "core/fit/study.h"
#include "core/model/aggregation.h"
#include "core/model/barrel_profile.h"
#include "core/model/metrics.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "core/sim/simulator.h"

namespace rollwear {

// A simulated mill (Wang, option 1 truth) and its centre calibration on
// the default split.
struct CalibratedMill {
  Simulation sim;
  CampaignSplit split;
  WearModel model;
};

inline CalibratedMill Calibrated(bool profiles, uint64_t seed = 11,
                                 int campaigns = 120) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  o.profiles = profiles;
  StatusOr<Simulation> sim = Simulate(o);
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  CalibratedMill out{std::move(*sim), {}, {}};
  const DatasetIndex index(out.sim.data);
  StatusOr<WearStatistics> st = Aggregate(out.sim.data, index, WearLaw::kWang);
  EXPECT_TRUE(st.ok()) << st.status().ToString();
  out.split = SplitCampaigns(*st);
  StatusOr<SplitCalibration> run =
      CalibrateOnSplit(*st, out.split, CalibrationOptions{});
  EXPECT_TRUE(run.ok()) << run.status().ToString();
  out.model = run->result.model;
  return out;
}

inline const CalibratedMill& WithoutProfiles() {
  static const CalibratedMill* mill = new CalibratedMill(Calibrated(false));
  return *mill;
}

inline const CalibratedMill& WithProfiles() {
  static const CalibratedMill* mill = new CalibratedMill(Calibrated(true));
  return *mill;
}

// A grinder point at x_mm of the roll that `meas` measured.
inline ProfilePoint ProfilePointOf(const Measurement& meas, double x_mm,
                                   double wear_um) {
  ProfilePoint p;
  p.campaign = meas.campaign;
  p.stand = meas.stand;
  p.position = meas.position;
  p.roll_id = meas.roll_id;
  p.measured_at = meas.measured_at;
  p.x_mm = x_mm;
  p.wear_um = wear_um;
  return p;
}

// Adds to `data` a profile of every measured roll generated with the
// model's form: pass wear from `model` (the fit's own K), spread by
// AddPassProfile with `shape`, read every 10 mm over the band the strips
// covered plus 40 mm, with N(0, noise_sd) per point; with `roll_scatter`,
// each roll's profile is also multiplied by its own N(1, roll_scatter)
// factor, which all its points share (recorded by (campaign, slot) in
// `factors` when given).
inline void AddModelProfiles(
    const WearModel& model, const ProfileShape& shape, double noise_sd,
    Dataset* data, double roll_scatter = 0,
    std::map<std::pair<int, int>, double>* factors = nullptr) {
  const DatasetIndex index(*data);
  const ProfileGrid grid;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0, noise_sd);
  std::normal_distribution<double> scatter(1, roll_scatter);
  for (const Measurement& meas : data->measurements) {
    const int slot = RollPositionSlot(meas.stand, meas.position);
    const int mi = index.MountOf(meas.campaign, slot);
    RollWearState state = MountedRollState(model, *data, meas.campaign, mi);
    std::vector<double> profile(grid.slices(), 0.0);
    double reach = 0;
    const double factor = roll_scatter > 0 ? scatter(rng) : 1;
    if (factors != nullptr) (*factors)[{meas.campaign, slot}] = factor;
    for (int pi : index.PassesOf(meas.campaign, meas.stand)) {
      const Pass& pass = data->passes[pi];
      const double w = AddPass(model, PassInputOf(*data, pass), &state);
      const double c =
          StripCentreMm(meas.position == Position::kTop, pass.shift_mm);
      AddPassProfile(grid, shape, w, c, pass.width_mm / 2, &profile);
      reach = std::max(reach, std::abs(c) + pass.width_mm / 2);
    }
    for (double x = -std::ceil((reach + 40) / 10) * 10; x <= reach + 40;
         x += 10) {
      data->profile_points.push_back(ProfilePointOf(
          meas, x, factor * grid.Interpolate(profile, x) + noise(rng)));
    }
  }
}

}  // namespace rollwear

#endif  // ROLLWEAR_TESTS_CORE_PROFILE_TEST_UTIL_H_
