// The simulator's grinder profiles across the barrel (SimulatorOptions::
// profiles): most measured rolls get one, they agree with the centre
// reading at x = 0, switching them on leaves every other draw alone, and
// shifting smears the box-wear edge peaks the truth's edge rise makes.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "core/sim/simulator.h"
#include "tests/core/dataset_test_util.h"

namespace rollwear {
namespace {

using ProfileKey = std::tuple<int, int, int>;  // campaign, stand, position

Simulation SimulateMill(uint64_t seed, bool profiles, bool shifting) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = 60;
  o.profiles = profiles;
  o.shifting = shifting;
  StatusOr<Simulation> sim = Simulate(o);
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  return std::move(*sim);
}

std::map<ProfileKey, std::vector<std::pair<double, double>>> Profiles(
    const Dataset& d) {
  std::map<ProfileKey, std::vector<std::pair<double, double>>> out;
  for (const ProfilePoint& p : d.profile_points) {
    out[{p.campaign, p.stand, static_cast<int>(p.position)}].emplace_back(
        p.x_mm, p.wear_um);
  }
  return out;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median over the profiles of (highest point) / (mean within 40 mm of the
// barrel centre): how far the edge peaks stand above the body.
double MedianPeakOverCentre(const Dataset& d) {
  std::vector<double> ratios;
  for (const auto& [key, points] : Profiles(d)) {
    double centre = 0, peak = 0;
    int n = 0;
    for (const auto& [x, w] : points) {
      if (std::abs(x) <= 40) centre += w, ++n;
      peak = std::max(peak, w);
    }
    ratios.push_back(peak / (centre / n));
  }
  return Median(ratios);
}

TEST(SimulatorProfileTest, MostMeasuredRollsHaveAProfileThatAgreesAtTheCentre) {
  const Simulation sim = SimulateMill(4, true, true);
  const Dataset& d = sim.data;
  const auto profiles = Profiles(d);
  const double share =
      static_cast<double>(profiles.size()) / d.measurements.size();
  EXPECT_GT(share, 0.75);
  EXPECT_LT(share, 0.95);
  // Profile at x = 0 minus the centre reading: the same roll scatter and
  // measurement offset, grinder noise 8 um and point noise 4 um.
  std::vector<double> diff;
  for (const Measurement& m : d.measurements) {
    auto it = profiles.find({m.campaign, m.stand, static_cast<int>(m.position)});
    if (it == profiles.end()) continue;
    for (const auto& [x, w] : it->second) {
      if (x == 0) diff.push_back(w - m.wear_center_um);
    }
  }
  ASSERT_EQ(diff.size(), profiles.size());
  double mean = 0, ss = 0;
  for (double v : diff) mean += v;
  mean /= diff.size();
  for (double v : diff) ss += (v - mean) * (v - mean);
  const double sd = std::sqrt(ss / (diff.size() - 1));
  EXPECT_LT(std::abs(mean), 3.0);
  EXPECT_GT(sd, 5.0);   // the two noises are there...
  EXPECT_LT(sd, 12.0);  // ...and nothing else: sqrt(8^2 + 4^2) = 8.9
  // Points every 10 mm; the truth records the shape and a noise floor.
  const auto& first = profiles.begin()->second;
  EXPECT_DOUBLE_EQ(first[1].first - first[0].first, 10.0);
  EXPECT_TRUE(sim.truth.has_profiles);
  EXPECT_GT(sim.truth.profile_noise_floor_um, 3.0);
  EXPECT_GT(sim.truth.profile_shape.edge_amplitude, 0);

  // Written and read back through the format's rules.
  const std::string dir = dataset_test::ScratchDir("rollwear_sim_profiles");
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(WriteDataset(d, dir).ok());
  StatusOr<Dataset> back = ReadDataset(dir);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->profile_points.size(), d.profile_points.size());
  std::filesystem::remove_all(dir);
}

TEST(SimulatorProfileTest, ProfilesLeaveEveryOtherDrawUnchanged) {
  const Simulation with = SimulateMill(5, true, true);
  const Simulation without = SimulateMill(5, false, true);
  EXPECT_TRUE(without.data.profile_points.empty());
  ASSERT_EQ(with.data.measurements.size(), without.data.measurements.size());
  for (size_t i = 0; i < with.data.measurements.size(); ++i) {
    EXPECT_EQ(with.data.measurements[i].wear_center_um,
              without.data.measurements[i].wear_center_um);
  }
  ASSERT_EQ(with.data.passes.size(), without.data.passes.size());
  EXPECT_EQ(with.data.passes.back().shift_mm,
            without.data.passes.back().shift_mm);
}

// Box wear: without shifting the strip edges of a width block fall on the
// same slices and the edge rise piles up into peaks; cyclic shifting
// spreads it over the stroke (the reason mills shift work rolls).
TEST(SimulatorProfileTest, ShiftingSmearsTheBoxWearEdgePeaks) {
  for (uint64_t seed : {4, 5, 6}) {
    const Simulation shifted = SimulateMill(seed, true, true);
    const Simulation fixed = SimulateMill(seed, true, false);
    for (const Pass& p : fixed.data.passes) ASSERT_EQ(p.shift_mm, 0);
    const double r_shifted = MedianPeakOverCentre(shifted.data);
    const double r_fixed = MedianPeakOverCentre(fixed.data);
    EXPECT_GT(r_fixed, r_shifted) << "seed " << seed;
    EXPECT_GT(r_fixed, 1.03) << "seed " << seed;
    std::printf("seed %llu: median peak / centre %.3f without shifting, %.3f with\n",
                static_cast<unsigned long long>(seed), r_fixed, r_shifted);
  }
}

}  // namespace
}  // namespace rollwear
