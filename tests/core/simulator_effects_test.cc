// Mill simulator, concealed effects: each effect moves the noise-free wear,
// relative to the baseline recomputed from the true factors, in the
// documented direction along its covariate, by a physically sensible
// amount.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using simulator_test::Correlation;
using simulator_test::MeasurementView;
using simulator_test::RatioAgainst;
using simulator_test::Simulated;
using simulator_test::Views;

constexpr int kEffectCampaigns = 80;

TEST(SimulatorEffectTest, CampaignGrowthRaisesWearOfLongCampaigns) {
  const Simulation sim = Simulated(21, kEffectCampaigns, {"campaign_growth"});
  const double beta = sim.truth.effects.at(0).parameters.at("beta");
  const double l_ref = sim.truth.effects.at(0).parameters.at("l_ref_m");
  std::vector<double> ratio, length;
  RatioAgainst(
      Views(sim), [](const MeasurementView& v) { return v.stand_length_m; },
      &ratio, &length);
  EXPECT_GT(Correlation(ratio, length), 0.9);
  for (size_t i = 0; i < ratio.size(); ++i) {
    // The multiplier grows linearly from 1 to 1 + beta L / L_ref, so the
    // campaign's mean lies near 1 + beta L / (2 L_ref).
    EXPECT_GT(ratio[i], 1 + 0.35 * beta * length[i] / l_ref);
    EXPECT_LT(ratio[i], 1 + 0.65 * beta * length[i] / l_ref);
  }
}

TEST(SimulatorEffectTest, RunInRaisesWearOfShortCampaignsMost) {
  const Simulation sim = Simulated(22, kEffectCampaigns, {"run_in"});
  const double beta = sim.truth.effects.at(0).parameters.at("beta");
  const double lambda = sim.truth.effects.at(0).parameters.at("lambda_m");
  std::vector<double> ratio, inverse_length;
  RatioAgainst(
      Views(sim), [](const MeasurementView& v) { return 1 / v.stand_length_m; },
      &ratio, &inverse_length);
  // The extra wear is about beta * lambda metres' worth, whatever the
  // campaign length: ratio - 1 ~ beta * lambda / L.
  EXPECT_GT(Correlation(ratio, inverse_length), 0.9);
  for (size_t i = 0; i < ratio.size(); ++i) {
    EXPECT_GT(ratio[i] - 1, 0.5 * beta * lambda * inverse_length[i]);
    EXPECT_LT(ratio[i] - 1, 1.5 * beta * lambda * inverse_length[i]);
  }
}

TEST(SimulatorEffectTest, WarmMeasurementReadsLessWearWhenCoolingIsShort) {
  const Simulation sim = Simulated(23, kEffectCampaigns, {"warm_measurement"});
  std::vector<std::pair<double, double>> by_cooling;  // (cooling_h, shift)
  for (const MeasurementView& v : Views(sim)) {
    by_cooling.emplace_back(v.cooling_h, v.noise_free - v.baseline);
  }
  std::sort(by_cooling.begin(), by_cooling.end());
  int early = 0, late = 0;
  for (size_t i = 0; i < by_cooling.size(); ++i) {
    const auto [cooling_h, shift] = by_cooling[i];
    EXPECT_LT(shift, 0);
    if (i > 0) {
      EXPECT_GE(shift, by_cooling[i - 1].second - 1e-9);
    }
    if (cooling_h < 3) {
      EXPECT_LT(shift, -25);
      ++early;
    }
    if (cooling_h > 30) {
      EXPECT_GT(shift, -1);
      ++late;
    }
  }
  EXPECT_GT(early, 5);
  EXPECT_GT(late, 0);
}

TEST(SimulatorEffectTest, ColderStripWearsMore) {
  const Simulation sim = Simulated(24, kEffectCampaigns, {"temperature"});
  std::vector<double> ratio, temperature;
  RatioAgainst(
      Views(sim), [](const MeasurementView& v) { return v.mean_temperature_c; },
      &ratio, &temperature);
  EXPECT_LT(Correlation(ratio, temperature), -0.9);
  const double lo = *std::min_element(ratio.begin(), ratio.end());
  const double hi = *std::max_element(ratio.begin(), ratio.end());
  EXPECT_GT(hi / lo, 1.15) << "effect must matter across campaigns";
}

TEST(SimulatorEffectTest, LubricatedCampaignsWearLessPerLoad) {
  const Simulation sim = Simulated(25, kEffectCampaigns, {"lubrication"});
  const double gamma = sim.truth.effects.at(0).parameters.at("gamma");
  std::vector<double> ratio, share;
  const std::vector<MeasurementView> views = Views(sim);
  RatioAgainst(
      views, [](const MeasurementView& v) { return v.lubricated_share; },
      &ratio, &share);
  EXPECT_LT(Correlation(ratio, share), -0.99);
  int lubricated = 0, dry = 0;
  for (size_t i = 0; i < views.size(); ++i) {
    if (!views[i].any_lubricated) {
      EXPECT_NEAR(ratio[i], 1, 1e-9);
      ++dry;
    } else {
      EXPECT_NEAR(ratio[i], 1 - gamma * share[i], 1e-9);
      EXPECT_GT(share[i], 0.8);
      ++lubricated;
    }
  }
  EXPECT_GT(lubricated, 40);
  EXPECT_GT(dry, 40);
  // The measured wear shows it too: lubricated campaigns wear less per unit
  // baseline load, by about gamma.
  double lub_sum = 0, dry_sum = 0;
  for (const MeasurementView& v : views) {
    (v.any_lubricated ? lub_sum : dry_sum) += v.measured / v.baseline;
  }
  EXPECT_LT((lub_sum / lubricated) / (dry_sum / dry), 1 - 0.6 * gamma);
}

TEST(SimulatorEffectTest, SofterRollsWearMore) {
  const Simulation sim = Simulated(26, kEffectCampaigns, {"hardness"});
  const double h_ref = sim.truth.effects.at(0).parameters.at("h_ref_hb");
  std::vector<double> ratio, hardness;
  RatioAgainst(
      Views(sim), [](const MeasurementView& v) { return v.hardness_hb; },
      &ratio, &hardness);
  EXPECT_LT(Correlation(ratio, hardness), -0.95);
  for (size_t i = 0; i < ratio.size(); ++i) {
    EXPECT_EQ(ratio[i] > 1, hardness[i] < h_ref) << hardness[i];
  }
}

TEST(SimulatorEffectTest, FasterRollsWearMore) {
  const Simulation sim = Simulated(27, kEffectCampaigns, {"speed"});
  std::vector<double> ratio, log_speed;
  RatioAgainst(
      Views(sim), [](const MeasurementView& v) { return v.mean_log_speed; },
      &ratio, &log_speed);
  EXPECT_GT(Correlation(ratio, log_speed), 0.9);
  const double lo = *std::min_element(ratio.begin(), ratio.end());
  const double hi = *std::max_element(ratio.begin(), ratio.end());
  EXPECT_GT(hi / lo, 1.1);
}

TEST(SimulatorEffectTest, AllEffectsTogether) {
  std::vector<std::string> names;
  for (const auto& [name, description] : SimulatorEffects())
    names.push_back(name);
  const Simulation sim = Simulated(28, 40, names);
  const std::vector<MeasurementView> views = Views(sim);
  double floor = 0;
  int changed = 0;
  for (const MeasurementView& v : views) {
    floor += std::abs(v.measured - v.noise_free) / views.size();
    changed += std::abs(v.noise_free / v.baseline - 1) > 0.02;
    EXPECT_GT(v.noise_free, 0);
  }
  EXPECT_NEAR(floor, sim.truth.noise_floor_um, 1e-9);
  EXPECT_GT(changed, static_cast<int>(views.size() * 9 / 10));
}

}  // namespace
}  // namespace rollwear
