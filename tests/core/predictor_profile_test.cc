// The predictor's profile state (core/model/predictor.h, TrackProfile): the
// per-slice sums after N coils, added pass by pass, equal the batch sums
// of the roll's campaign (ProfileStats over every pass's wear) to 1e-9,
// the default shape reads the centre wear at x = 0, and a pass's update
// stays in microseconds.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/pass_input.h"
#include "core/model/profile_interval.h"
#include "core/fit/study.h"
#include "core/model/aggregation.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "core/sim/simulator.h"

namespace rollwear {
namespace {

TEST(PredictorProfileTest, IncrementalSumsEqualTheBatchSums) {
  SimulatorOptions o;
  o.seed = 5;
  o.num_campaigns = 12;
  o.profiles = true;
  StatusOr<Simulation> sim = Simulate(o);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  const Dataset& data = sim->data;
  const DatasetIndex index(data);
  StatusOr<WearStatistics> st = Aggregate(data, index, WearLaw::kWang);
  ASSERT_TRUE(st.ok()) << st.status().ToString();
  StatusOr<SplitCalibration> run =
      CalibrateOnSplit(*st, SplitCampaigns(*st), CalibrationOptions{});
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  const WearModel& model = run->result.model;
  int rolls = 0;
  double seconds = 0;
  long passes = 0;
  for (int c = 0; c < static_cast<int>(data.campaigns.size()); ++c) {
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      const int mi = index.MountOf(c, slot);
      if (mi < 0) continue;
      const Mount& mount = data.mounts[mi];
      RollWearState live = MountedRollState(model, data, c, mi);
      TrackProfile(&live);
      RollWearState batch_state = MountedRollState(model, data, c, mi);
      ProfileStats batch{ProfileGrid()};
      for (int pi : index.PassesOf(c, mount.stand)) {
        const Pass& pass = data.passes[pi];
        const PassInput in = PassInputOf(data, pass);
        const auto t0 = std::chrono::steady_clock::now();
        AddPass(model, in, &live);
        seconds += std::chrono::duration<double>(
                       std::chrono::steady_clock::now() - t0)
                       .count();
        ++passes;
        const double w = AddPass(model, in, &batch_state);
        batch.AddPass(w,
                      (mount.position == Position::kTop ? -1 : 1) * pass.shift_mm,
                      pass.width_mm / 2);
      }
      ASSERT_TRUE(live.profile.has_value());
      const ProfileGrid grid;
      double max_sum = 0;
      for (int j = 0; j < grid.slices(); ++j) {
        for (int i = 0; i < kProfileBasis; ++i) {
          max_sum = std::max(max_sum, std::abs(batch.slice(j)[i]));
        }
      }
      ASSERT_GT(max_sum, 0);
      for (int j = 0; j < grid.slices(); ++j) {
        for (int i = 0; i < kProfileBasis; ++i) {
          ASSERT_NEAR(live.profile->slice(j)[i], batch.slice(j)[i],
                      1e-9 * max_sum)
              << "slice " << j << " basis " << i;
        }
      }
      // g = 1: the centre slice reads the centre wear (strips cover x = 0).
      const ProfilePrediction p =
          PredictProfile(*live.profile, nullptr, live.wear_um,
                         WearInterval(model, live));
      EXPECT_NEAR(p.wear_um[grid.slices() / 2], live.wear_um,
                  1e-9 * live.wear_um);
      ++rolls;
    }
  }
  EXPECT_GT(rolls, 10);
  const double us = 1e6 * seconds / static_cast<double>(passes);
  std::printf("per-pass update with the profile: %.2f us over %ld passes\n",
              us, passes);
  EXPECT_LT(us, 50);  // microseconds, with room for a loaded machine
}

}  // namespace
}  // namespace rollwear
