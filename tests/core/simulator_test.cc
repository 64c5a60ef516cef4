// Mill simulator: determinism, paper-shaped counts, the data format's rules
// on every row, physical rolls, wear range, and the truth (noise-free wear
// recomputed here from the true factors, noise floor against its analytic
// expectation). The concealed effects are tested in simulator_effects_test.cc.
#include "core/sim/simulator.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/covariates.h"
#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"
#include "core/model/wear_law.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using simulator_test::MeasurementView;
using simulator_test::Simulated;
using simulator_test::Views;

// The paper-sized mill without effects (default options), built once.
const Simulation& PaperMill() {
  static const Simulation* sim =
      new Simulation(Simulated(SimulatorOptions{}.seed, 395));
  return *sim;
}

// First field in which two datasets differ, or "" when they are identical.
std::string FirstDifference(const Dataset& a, const Dataset& b) {
  auto size = [](const char* what, size_t x, size_t y) {
    return x == y ? std::string()
                  : std::string(what) + " count " + std::to_string(x) + " vs " +
                        std::to_string(y);
  };
  for (std::string d :
       {size("campaigns", a.campaigns.size(), b.campaigns.size()),
        size("mounts", a.mounts.size(), b.mounts.size()),
        size("passes", a.passes.size(), b.passes.size()),
        size("measurements", a.measurements.size(), b.measurements.size())}) {
    if (!d.empty()) return d;
  }
  if (a.grades != b.grades) return "grade labels";
  if (a.roll_types != b.roll_types) return "roll type labels";
  if (a.coil_ids != b.coil_ids) return "coil ids";
  for (size_t i = 0; i < a.campaigns.size(); ++i) {
    const Campaign &x = a.campaigns[i], &y = b.campaigns[i];
    if (x.id != y.id || x.started_at != y.started_at ||
        x.ended_at != y.ended_at) {
      return "campaign " + std::to_string(i);
    }
  }
  for (size_t i = 0; i < a.mounts.size(); ++i) {
    const Mount &x = a.mounts[i], &y = b.mounts[i];
    if (x.campaign != y.campaign || x.stand != y.stand ||
        x.position != y.position || x.roll_id != y.roll_id ||
        x.roll_type != y.roll_type || x.diameter_mm != y.diameter_mm ||
        x.hardness_hb != y.hardness_hb) {
      return "mount " + std::to_string(i);
    }
  }
  for (size_t i = 0; i < a.passes.size(); ++i) {
    const Pass &x = a.passes[i], &y = b.passes[i];
    if (x.campaign != y.campaign || x.coil != y.coil || x.seq != y.seq ||
        x.rolled_at != y.rolled_at || x.grade != y.grade ||
        x.stand != y.stand || x.force_kn != y.force_kn ||
        x.width_mm != y.width_mm || x.length_m != y.length_m ||
        x.entry_thickness_mm != y.entry_thickness_mm ||
        x.exit_thickness_mm != y.exit_thickness_mm ||
        x.temperature_c != y.temperature_c || x.speed_mps != y.speed_mps ||
        x.lubrication != y.lubrication || x.shift_mm != y.shift_mm) {
      return "pass " + std::to_string(i);
    }
  }
  for (size_t i = 0; i < a.measurements.size(); ++i) {
    const Measurement &x = a.measurements[i], &y = b.measurements[i];
    if (x.campaign != y.campaign || x.stand != y.stand ||
        x.position != y.position || x.roll_id != y.roll_id ||
        x.measured_at != y.measured_at ||
        x.wear_center_um != y.wear_center_um) {
      return "measurement " + std::to_string(i);
    }
  }
  return "";
}

// One measurement seen through the rows it aggregates: the baseline wear

TEST(SimulatorTest, SameSeedGivesIdenticalDatasetAndTruth) {
  const std::vector<std::string> all = {"campaign_growth", "warm_measurement",
                                        "lubrication"};
  const Simulation a = Simulated(17, 25, all, 0.1);
  const Simulation b = Simulated(17, 25, all, 0.1);
  EXPECT_EQ(FirstDifference(a.data, b.data), "");
  EXPECT_EQ(a.truth.noise_free_wear_um, b.truth.noise_free_wear_um);
  EXPECT_EQ(a.truth.noise_floor_um, b.truth.noise_floor_um);
}

TEST(SimulatorTest, DifferentSeedsDiffer) {
  const Simulation a = Simulated(1, 10);
  const Simulation b = Simulated(2, 10);
  EXPECT_NE(FirstDifference(a.data, b.data), "");
  ASSERT_EQ(a.data.measurements.size(), b.data.measurements.size());
  int same = 0;
  for (size_t i = 0; i < a.data.measurements.size(); ++i) {
    same += a.data.measurements[i].wear_center_um ==
            b.data.measurements[i].wear_center_um;
  }
  EXPECT_LT(same, 3);
}

TEST(SimulatorTest, CampaignsArePrefixStableAcrossLengths) {
  // Per-campaign random streams: a shorter run is the head of a longer one.
  const Simulation shorter = Simulated(5, 6);
  const Simulation longer = Simulated(5, 12);
  for (size_t i = 0; i < shorter.data.campaigns.size(); ++i) {
    EXPECT_EQ(shorter.data.campaigns[i].ended_at,
              longer.data.campaigns[i].ended_at);
  }
  for (size_t i = 0; i < shorter.data.measurements.size(); ++i) {
    EXPECT_EQ(shorter.data.measurements[i].wear_center_um,
              longer.data.measurements[i].wear_center_um);
  }
}

TEST(SimulatorTest, PaperShapedCounts) {
  const Dataset& d = PaperMill().data;
  EXPECT_EQ(d.campaigns.size(), 395u);
  EXPECT_NEAR(static_cast<double>(d.coil_ids.size()), 51700, 0.03 * 51700);
  EXPECT_EQ(d.passes.size(), 2 * d.coil_ids.size());
  EXPECT_EQ(d.mounts.size(), 4u * 395);
  EXPECT_EQ(d.measurements.size(), 1580u);
  EXPECT_EQ(d.roll_types.size(), 8u);
  EXPECT_EQ(d.grades.size(), 9u);
  std::map<int, int> mounts_per_campaign;
  for (const Mount& m : d.mounts) ++mounts_per_campaign[m.campaign];
  EXPECT_EQ(mounts_per_campaign.size(), 395u);
  for (const auto& [c, n] : mounts_per_campaign) EXPECT_EQ(n, 4) << c;
  // Campaign lengths vary around 131 coils (80..190).
  std::map<int, int> coils;
  for (const Pass& p : d.passes) coils[p.campaign] += p.stand == 7;
  int shortest = 1 << 30, longest = 0;
  for (const auto& [c, n] : coils) {
    shortest = std::min(shortest, n);
    longest = std::max(longest, n);
  }
  EXPECT_GE(shortest, 75);
  EXPECT_LT(shortest, 100);
  EXPECT_GT(longest, 170);
  EXPECT_LE(longest, 195);
  // Physical rolls recur after regrinding (an inventory of 12..16 rolls per
  // type); some reach their scrap diameter and new rolls (>= 752 mm) come in.
  std::map<std::string, std::pair<const Mount*, const Mount*>> first_last;
  std::map<std::string, int> uses;
  for (const Mount& m : d.mounts) {
    ++uses[m.roll_id];
    auto& fl = first_last[m.roll_id];
    if (fl.first == nullptr) fl.first = &m;
    fl.second = &m;
  }
  int most = 0;
  for (const auto& [id, n] : uses) most = std::max(most, n);
  EXPECT_GE(most, 8);
  EXPECT_GT(uses.size(), 8u * 12);
  EXPECT_LT(uses.size(), 200u);
  int scrapped = 0, replacements = 0;
  for (const auto& [id, fl] : first_last) {
    scrapped += fl.second->campaign < 350 && fl.second->diameter_mm < 672;
    replacements += fl.first->campaign >= 50 && fl.first->diameter_mm >= 752;
  }
  EXPECT_GE(scrapped, 5);
  EXPECT_GE(replacements, 5);
}

TEST(SimulatorTest, MissingFractionDropsMeasurementsOnly) {
  const Simulation full = Simulated(9, 200);
  const Simulation gappy = Simulated(9, 200, {}, 0.2);
  const double n = static_cast<double>(gappy.data.measurements.size());
  EXPECT_NEAR(n, 0.8 * 800, 4 * std::sqrt(800 * 0.2 * 0.8));
  EXPECT_EQ(gappy.truth.noise_free_wear_um.size(),
            gappy.data.measurements.size());
  EXPECT_EQ(gappy.truth.noise_free_keys.size(), gappy.data.measurements.size());
  // The kept rows are exactly the rows of the complete run.
  std::map<std::tuple<int, int, int>, double> complete;
  for (const Measurement& m : full.data.measurements) {
    complete[{m.campaign, m.stand, static_cast<int>(m.position)}] =
        m.wear_center_um;
  }
  for (const Measurement& m : gappy.data.measurements) {
    EXPECT_EQ(m.wear_center_um,
              complete.at({m.campaign, m.stand, static_cast<int>(m.position)}));
  }
  EXPECT_EQ(Simulated(9, 5, {}, 1.0).data.measurements.size(), 0u);
}

TEST(SimulatorTest, EveryRowSatisfiesTheDataFormat) {
  const Dataset& d = PaperMill().data;
  for (size_t c = 0; c < d.campaigns.size(); ++c) {
    const Campaign& cp = d.campaigns[c];
    EXPECT_LT(cp.started_at, cp.ended_at);
    if (c > 0) {
      const UnixSeconds change = cp.started_at - d.campaigns[c - 1].ended_at;
      EXPECT_GE(change, 20 * 60) << cp.id;  // roll change 20..40 min
    }
  }
  std::set<std::tuple<int, int, int>> mount_keys;
  std::map<std::tuple<int, int, int>, std::string> roll_of;
  for (const Mount& m : d.mounts) {
    EXPECT_TRUE(
        mount_keys.insert({m.campaign, m.stand, static_cast<int>(m.position)})
            .second);
    EXPECT_TRUE(m.stand == 6 || m.stand == 7);
    EXPECT_GE(m.diameter_mm, 650);
    EXPECT_LE(m.diameter_mm, 765);
    EXPECT_GT(m.hardness_hb, 400);
    EXPECT_LT(m.hardness_hb, 700);
    roll_of[{m.campaign, m.stand, static_cast<int>(m.position)}] = m.roll_id;
  }
  std::map<std::pair<int, int>, int> last_seq;  // (campaign, stand) -> seq
  std::map<int, std::pair<double, double>> coil_thickness;  // F6 exit, F7 entry
  std::map<int, std::pair<double, double>> coil_volume;     // L * h per stand
  for (const Pass& p : d.passes) {
    const Campaign& cp = d.campaigns[p.campaign];
    EXPECT_GT(p.force_kn, 0);
    EXPECT_GE(p.width_mm, 900);
    EXPECT_LE(p.width_mm, 1650);
    EXPECT_GT(p.length_m, 0);
    EXPECT_GT(p.exit_thickness_mm, 0);
    EXPECT_LT(p.exit_thickness_mm, p.entry_thickness_mm);
    EXPECT_GT(p.speed_mps, 0);
    EXPECT_GE(p.temperature_c, 840);
    EXPECT_LE(p.temperature_c, 970);
    EXPECT_LE(std::abs(p.shift_mm), 150);
    EXPECT_GE(p.rolled_at, cp.started_at);
    EXPECT_LE(p.rolled_at, cp.ended_at);
    int& seq = last_seq[{p.campaign, p.stand}];
    EXPECT_EQ(p.seq, seq + 1)
        << "seq must run 1, 2, ... per campaign and stand";
    seq = p.seq;
    if (p.stand == 7) {
      EXPECT_GE(p.exit_thickness_mm, 1.5);
      EXPECT_LE(p.exit_thickness_mm, 8.0);
      EXPECT_GE(p.speed_mps, 5.8);
      EXPECT_LE(p.speed_mps, 15.5);
      coil_thickness[p.coil].second = p.entry_thickness_mm;
      coil_volume[p.coil].second = p.length_m * p.exit_thickness_mm;
    } else {
      coil_thickness[p.coil].first = p.exit_thickness_mm;
      coil_volume[p.coil].first = p.length_m * p.exit_thickness_mm;
    }
  }
  EXPECT_EQ(coil_thickness.size(), d.coil_ids.size());
  for (const auto& [coil, h] : coil_thickness) EXPECT_EQ(h.first, h.second);
  // Volume constancy: L6 h6 = L7 h7 up to the rounding of L to 0.1 m.
  for (const auto& [coil, v] : coil_volume) {
    EXPECT_NEAR(v.first / v.second, 1, 2e-3) << d.coil_ids[coil];
  }
  std::set<std::string> ids(d.coil_ids.begin(), d.coil_ids.end());
  EXPECT_EQ(ids.size(), d.coil_ids.size());
  std::set<std::tuple<int, int, int>> measured;
  for (const Measurement& m : d.measurements) {
    const auto key =
        std::make_tuple(m.campaign, m.stand, static_cast<int>(m.position));
    EXPECT_TRUE(measured.insert(key).second);
    EXPECT_EQ(m.roll_id, roll_of.at(key));
    EXPECT_GT(m.wear_center_um, 0);
    const double cooling_h =
        (m.measured_at - d.campaigns[m.campaign].ended_at) / 3600.0;
    EXPECT_GE(cooling_h, 1.0 - 1e-9);
    EXPECT_LE(cooling_h, 48.0 + 1e-9);
  }
}

TEST(SimulatorTest, PhysicalRollsAreReground) {
  // A roll is mounted once per campaign; its next mount comes after its
  // measurement, at a smaller diameter and no higher hardness.
  const Dataset& d = PaperMill().data;
  std::map<std::string, std::vector<const Mount*>> history;
  std::map<std::pair<int, std::string>, UnixSeconds> measured_at;
  for (const Mount& m : d.mounts) history[m.roll_id].push_back(&m);
  for (const Measurement& m : d.measurements)
    measured_at[{m.campaign, m.roll_id}] = m.measured_at;
  int remounts = 0;
  for (const auto& [id, mounts] : history) {
    for (size_t i = 1; i < mounts.size(); ++i) {
      const Mount& a = *mounts[i - 1];
      const Mount& b = *mounts[i];
      ASSERT_LT(a.campaign, b.campaign) << id;
      EXPECT_EQ(a.roll_type, b.roll_type);
      EXPECT_LT(b.diameter_mm, a.diameter_mm - 0.5) << id;
      EXPECT_LE(b.hardness_hb, a.hardness_hb) << id;
      EXPECT_GT(d.campaigns[b.campaign].started_at,
                measured_at.at({a.campaign, id}));
      ++remounts;
    }
  }
  EXPECT_GT(remounts, 1000);
}

TEST(SimulatorTest, DatasetRoundTripsThroughCsv) {
  const Simulation sim = Simulated(3, 12, {"warm_measurement"}, 0.1);
  const std::string dir =
      (std::filesystem::temp_directory_path() /
       ("rollwear_simulator_test_" + std::to_string(::getpid())))
          .string();
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(WriteDataset(sim.data, dir).ok());
  StatusOr<Dataset> back = ReadDataset(dir);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(FirstDifference(sim.data, *back), "");

  std::filesystem::remove_all(dir);
}

TEST(SimulatorTest, WearRangeIsPaperLike) {
  const Dataset& d = PaperMill().data;
  std::vector<double> w;
  for (const Measurement& m : d.measurements) w.push_back(m.wear_center_um);
  std::sort(w.begin(), w.end());
  const double median = w[w.size() / 2];
  EXPECT_GT(median, 150);
  EXPECT_LT(median, 350);
  const double above_300 =
      static_cast<double>(w.end() -
                          std::upper_bound(w.begin(), w.end(), 300.0)) /
      w.size();
  EXPECT_GT(above_300, 0.08);
  EXPECT_LT(above_300, 0.40);
  EXPECT_GT(w[w.size() / 10], 80);       // p10
  EXPECT_LT(w[w.size() * 9 / 10], 500);  // p90
  EXPECT_LT(w.back(), 1000);
}

TEST(SimulatorTest, NoiseFreeWearIsWangLawWithTrueFactors) {
  const Simulation& sim = PaperMill();
  ASSERT_EQ(sim.truth.noise_free_wear_um.size(), sim.data.measurements.size());
  EXPECT_EQ(sim.truth.law, "wang");
  EXPECT_EQ(sim.truth.k_position.size(), 4u);
  EXPECT_EQ(sim.truth.k_roll_type.size(), 8u);
  EXPECT_EQ(sim.truth.k_grade.size(), 9u);
  EXPECT_TRUE(sim.truth.effects.empty());
  for (const MeasurementView& v : Views(sim)) {
    ASSERT_NEAR(v.noise_free / v.baseline, 1, 1e-9);
  }
  for (size_t i = 0; i < sim.data.measurements.size(); ++i) {
    const Measurement& m = sim.data.measurements[i];
    const SimulatedMeasurementKey& k = sim.truth.noise_free_keys[i];
    EXPECT_EQ(k.campaign_id, sim.data.campaigns[m.campaign].id);
    EXPECT_EQ(k.stand, m.stand);
    EXPECT_EQ(k.position, m.position);
  }
}

TEST(SimulatorTest, NoiseFloorNearAnalyticExpectation) {
  // measured - noise_free = (S - 1) W + e with S lognormal (mean 1, log-sd
  // s, so sd(S) = sqrt(exp(s^2) - 1)) and e ~ N(0, g^2). Treating the sum
  // as normal, E|.| = sqrt(2/pi) * sqrt(sd(S)^2 W^2 + g^2).
  const Simulation& sim = PaperMill();
  const SimulationTruth& t = sim.truth;
  EXPECT_EQ(t.grinder_noise_sd_um, 8);
  EXPECT_NEAR(t.roll_scatter_sd, 0.09, 0.02);
  const double sd_s =
      std::sqrt(std::exp(t.roll_scatter_sd * t.roll_scatter_sd) - 1);
  double expected = 0, observed = 0;
  const size_t n = sim.data.measurements.size();
  for (size_t i = 0; i < n; ++i) {
    const double w = t.noise_free_wear_um[i];
    expected += std::sqrt(2 / kPi) *
                std::sqrt(sd_s * sd_s * w * w +
                          t.grinder_noise_sd_um * t.grinder_noise_sd_um);
    observed += std::abs(sim.data.measurements[i].wear_center_um - w);
  }
  expected /= n;
  observed /= n;
  EXPECT_NEAR(t.noise_floor_um, observed, 1e-9);
  EXPECT_NEAR(t.noise_floor_um / expected, 1, 0.06)
      << "floor " << t.noise_floor_um << " expected " << expected;
}

TEST(SimulatorTest, OptionsAreValidated) {
  std::string error;
  SimulatorOptions o;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.effects = {"campaign_growth", "no_such_effect"};
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("no_such_effect"), std::string::npos);
  EXPECT_NE(error.find("lubrication"), std::string::npos)
      << "lists valid names";
  EXPECT_EQ(Simulate(o).status().code(), StatusCode::kInvalidArgument);
  o.effects = {"speed", "speed"};
  EXPECT_FALSE(o.IsValid(&error));
  o.effects = {};
  o.num_campaigns = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o.num_campaigns = 10;
  o.missing_measurement_fraction = 1.5;
  EXPECT_FALSE(o.IsValid(&error));
  o.missing_measurement_fraction = 0;
  o.coils_per_campaign = std::nan("");
  EXPECT_FALSE(o.IsValid(&error));
}

TEST(SimulatorTest, EffectsAreListedWithCanonicalCovariates) {
  // The canonical covariates of the data format (core/model/covariates.h).
  std::set<std::string> canonical;
  for (const CovariateSpec& c : CovariateCatalog(Dataset{})) canonical.insert(c.name);
  EXPECT_GT(canonical.size(), 15u);
  std::vector<std::string> names;
  for (const auto& [name, description] : SimulatorEffects()) {
    names.push_back(name);
    EXPECT_FALSE(description.empty());
  }
  for (const char* required :
       {"campaign_growth", "run_in", "warm_measurement", "temperature",
        "lubrication", "hardness", "speed", "supplier_change", "reduction", "diameter",
        "gross_errors"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end())
        << required;
  }
  const Simulation sim = Simulated(4, 3, names);
  ASSERT_EQ(sim.truth.effects.size(), names.size());
  for (const SimulatedEffect& e : sim.truth.effects) {
    if (e.name == "gross_errors") {  // acts through no recorded quantity
      EXPECT_EQ(e.covariate, "");
      EXPECT_FALSE(e.parameters.empty());
      continue;
    }
    EXPECT_FALSE(e.parameters.empty()) << e.name;
    if (!e.form.empty()) {  // an effect family (sim_families.cc)
      if (!e.expressible || e.null_effect) {
        EXPECT_TRUE(e.expressible ? e.covariate.empty() || e.null_effect
                                  : e.covariate.empty() && !e.mismatch.empty())
            << e.name;
        continue;
      }
      // Also the format's factor and timestamp columns, and the text
      // column of measurements.csv the family adds.
      const auto& x = sim.data.measurement_extra.factor_names;
      if (e.covariate == "grade" || e.covariate == "roll_type" ||
          e.covariate == "rolled_at" || e.covariate == "measured_at" ||
          std::find(x.begin(), x.end(), e.covariate) != x.end()) {
        continue;
      }
    }
    EXPECT_TRUE(canonical.count(e.covariate)) << e.name << ": " << e.covariate;
  }
}

}  // namespace
}  // namespace rollwear
