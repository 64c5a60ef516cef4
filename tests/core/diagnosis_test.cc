// The diagnosis engine on the simulator's concealed effects: it must name
// the right covariate and a mechanism of the right shape without being told
// which effect is present, bring the validation gap to within 15 % of the
// noise floor, find two effects at once, and stay quiet on data without any
// effect. One code path and the default options everywhere.
#include "core/diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/report/diagnosis_report.h"
#include "core/model/model_terms.h"
#include "core/model/predictor.h"
#include "core/sim/simulator.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

// Paper-size mills (395 campaigns) everywhere in Release. Under the
// sanitizers (test_size.h) the tests marked "reduced" run Diagnose on 200
// campaigns, about half its time, with the same assertions: each passed
// at 200 campaigns in Release. The others stay at 395 there too (at 200,
// supplier_change seed 303 gains a second finding and the under-
// prediction above 300 µm loses its significance).
constexpr int kReducedCampaigns = test_size::FullOr(395, 200);
// The 30 ConcealedEffectTest cases: 300 campaigns under the sanitizers
// (they were ≈ 22 CPU-min of the ASan phase at 395), the first seed of
// each effect only (kConcealedSeeds). All 30 passed in
// Release at 300 and at 250 campaigns (session 13); 300 keeps a margin.
constexpr int kConcealedCampaigns = test_size::FullOr(395, 300);

Simulation Simulated(uint64_t seed, std::vector<std::string> effects,
                     int campaigns = 395) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  o.effects = std::move(effects);
  StatusOr<Simulation> s = Simulate(o);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return std::move(s).value();
}

// Noise floor of the report's validation measurements: mean |measured -
// noise-free| from the simulator's truth.
double ValidationNoiseFloor(const Simulation& sim, const DiagnosisReport& r) {
  std::map<std::tuple<std::string, int, int>, double> noise_free;
  for (size_t i = 0; i < sim.data.measurements.size(); ++i) {
    const Measurement& m = sim.data.measurements[i];
    noise_free[{sim.data.campaigns[m.campaign].id, m.stand, static_cast<int>(m.position)}] =
        sim.truth.noise_free_wear_um[i];
  }
  double sum = 0;
  int n = 0;
  for (const DiagnosisPoint& p : r.points) {
    if (!p.validation) continue;
    sum += std::abs(p.measured_um -
                    noise_free.at({p.campaign_id, p.stand, static_cast<int>(p.position)}));
    ++n;
  }
  return sum / n;
}

struct Expected {
  const char* effect;
  const char* covariate;
  std::set<std::string> shapes;
  const char* mechanism;
};

const Expected kExpected[] = {
    {"campaign_growth", "campaign_length_before_m", {"increasing", "saturating_growth"},
     "wear_rate_growth_along_campaign"},
    {"run_in", "campaign_length_before_m", {"decaying"}, "run_in_of_fresh_surface"},
    {"warm_measurement", "cooling_h", {"reads_low_when_measured_early"},
     "thermal_expansion_at_measurement"},
    {"temperature", "temperature_c", {"decreasing"}, "cold_strip_hardness_and_scale"},
    {"lubrication", "lubrication", {"lower_when_on"}, "roll_gap_lubrication"},
    {"hardness", "hardness_hb", {"decreasing"}, "roll_hardness"},
    {"speed", "speed_mps", {"increasing"}, "rolling_speed"},
    {"supplier_change", "started_at", {"step_up", "increasing", "saturating_growth"},
     "drift_over_time"},
    {"reduction", "reduction", {"increasing"}, "roll_gap_slip"},
    {"diameter", "diameter_mm", {"decreasing"}, "roll_diameter"},
};

// Three seeds per effect; one (the first) under the sanitizers, where the
// memory and UB checks need each effect's path once.
const std::vector<uint64_t> kConcealedSeeds =
    test_size::kSanitized ? std::vector<uint64_t>{101u}
                          : std::vector<uint64_t>{101u, 202u, 303u};

class ConcealedEffectTest : public ::testing::TestWithParam<std::tuple<int, uint64_t>> {};

TEST_P(ConcealedEffectTest, NamesCovariateAndShapeAndReachesNoiseFloor) {
  const Expected& e = kExpected[std::get<0>(GetParam())];
  const uint64_t seed = std::get<1>(GetParam());
  const Simulation sim = Simulated(seed, {e.effect}, kConcealedCampaigns);
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->verdict, "missing_physics_found") << e.effect << " seed " << seed;
  ASSERT_FALSE(r->findings.empty());
  const Finding& f = r->findings.front();
  EXPECT_EQ(f.covariate, e.covariate) << e.effect << " seed " << seed;
  EXPECT_TRUE(e.shapes.count(f.shape) > 0) << e.effect << " shape " << f.shape;
  EXPECT_EQ(f.mechanism, e.mechanism);
  EXPECT_LT(f.p_adjusted, 1e-3);
  EXPECT_LT(f.gap_val_after_um, f.gap_val_before_um);
  const double floor = ValidationNoiseFloor(sim, *r);
  EXPECT_LT(r->final_gap_val_um, 1.15 * floor)
      << e.effect << " seed " << seed << ": gap " << r->final_gap_val_um << " floor " << floor;
  // A single concealed effect must not produce a spurious second finding.
  EXPECT_LE(r->findings.size(), 1u) << "second finding: " << r->findings.back().covariate;
}

INSTANTIATE_TEST_SUITE_P(
    EveryEffectSeveralSeeds, ConcealedEffectTest,
    ::testing::Combine(::testing::Range(0, static_cast<int>(std::size(kExpected))),
                       ::testing::ValuesIn(kConcealedSeeds)),
    [](const ::testing::TestParamInfo<ConcealedEffectTest::ParamType>& info) {
      return std::string(kExpected[std::get<0>(info.param)].effect) + "_seed" +
             std::to_string(std::get<1>(info.param));
    });

TEST(DiagnosisTest, FindsTwoEffectsAtOnce) {  // reduced
  const std::vector<std::pair<std::vector<std::string>, std::set<std::string>>> cases = {
      {{"campaign_growth", "lubrication"}, {"campaign_length_before_m", "lubrication"}},
      {{"warm_measurement", "hardness"}, {"cooling_h", "hardness_hb"}},
  };
  for (const auto& [effects, covariates] : cases) {
    const Simulation sim = Simulated(77, effects, kReducedCampaigns);
    StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
    ASSERT_TRUE(r.ok());
    std::set<std::string> found;
    for (const Finding& f : r->findings) found.insert(f.covariate);
    EXPECT_EQ(found, covariates) << effects[0] << " + " << effects[1];
    EXPECT_LT(r->final_gap_val_um, 1.15 * ValidationNoiseFloor(sim, *r));
  }
}

// The study saw every model under-predict wear above ~300 µm. With the
// campaign-position effect concealed the report must show that before and
// its removal after.
TEST(DiagnosisTest, RemovesUnderPredictionOfLargeWear) {
  const Simulation sim = Simulated(5, {"campaign_growth"});
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->verdict, "missing_physics_found");
  // Residuals of campaigns whose baseline prediction is >= 300 µm: mean and
  // t statistic (mean / standard error) before and after.
  std::vector<double> before, after;
  for (const DiagnosisPoint& p : r->points) {
    if (p.before_um < 300) continue;
    before.push_back(p.measured_um - p.before_um);
    after.push_back(p.measured_um - p.after_um);
  }
  ASSERT_GT(before.size(), 30u);
  auto mean_t = [](const std::vector<double>& v, double* t) {
    double m = 0, s2 = 0;
    for (double x : v) m += x;
    m /= v.size();
    for (double x : v) s2 += (x - m) * (x - m);
    *t = m / std::sqrt(s2 / (v.size() - 1) / v.size());
    return m;
  };
  double t_before, t_after;
  const double m_before = mean_t(before, &t_before), m_after = mean_t(after, &t_after);
  EXPECT_GT(m_before, 5.0) << "baseline under-predicts large wear";
  EXPECT_GT(t_before, 3.0) << "and significantly so";
  EXPECT_LT(std::abs(m_after), m_before / 3) << "after " << m_after << " before " << m_before;
  EXPECT_LT(std::abs(t_after), 2.0);
  bool amplitude_located = false;
  for (const Breakdown& b : r->locate) {
    if (b.dimension == "wear_amplitude") amplitude_located = b.p_value < 1e-3;
  }
  EXPECT_TRUE(amplitude_located);
  const std::string html = DiagnosisHtml(*r);
  EXPECT_NE(html.find("wear_rate_growth_along_campaign"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("&gt;= 300 µm"), std::string::npos);
}

// The adopted model (option 1 + terms) predicts coil by coil, as the daemon
// will, exactly what the diagnosis computed in batch.
TEST(DiagnosisTest, AdoptedModelPredictsCoilByCoilAsInBatch) {  // reduced
  const Simulation sim = Simulated(9, {"run_in"}, kReducedCampaigns);
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->verdict, "missing_physics_found");
  const WearModel& m = r->adopted_model;
  ASSERT_EQ(m.terms.size(), r->findings.size());
  const Dataset& d = sim.data;
  const DatasetIndex index(d);
  std::map<std::tuple<std::string, int, int>, double> after;
  for (const DiagnosisPoint& p : r->points) {
    after[{p.campaign_id, p.stand, static_cast<int>(p.position)}] = p.after_um;
  }
  int checked = 0;
  for (size_t c = 0; c < d.campaigns.size() && checked < 200; ++c) {
    for (int slot : index.slots()) {
      const int mi = index.MountOf(static_cast<int>(c), slot);
      auto it = after.find({d.campaigns[c].id, SlotStand(slot), slot % 2});
      if (mi < 0 || it == after.end()) continue;
      const Mount& mount = d.mounts[mi];
      RollWearState state = MountRoll(m, RollPositionName(mount.stand, mount.position),
                                      d.roll_types[mount.roll_type], mount.diameter_mm,
                                      mount.hardness_hb, d.campaigns[c].started_at);
      for (int pi : index.PassesOf(static_cast<int>(c), mount.stand)) {
        const Pass& p = d.passes[pi];
        AddPass(m, PassInputOf(d, p), &state);
      }
      EXPECT_NEAR(state.wear_um, it->second, 1e-9 * it->second);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 200);
}

// No concealed effect: quiet in at least 95 % of 20 seeds.
// Seeds 1000-1019 (1000-1004 under the sanitizers): at least 19 of 20 (4 of
// 5) quiet.
TEST(DiagnosisTest, QuietWithoutConcealedEffect) {  // reduced
  const int num_seeds = test_size::FullOr(20, 5);
  int quiet = 0;
  std::string spurious;
  for (uint64_t seed = 1000; seed < 1000u + num_seeds; ++seed) {
    const Simulation sim = Simulated(seed, {}, kReducedCampaigns);
    StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
    ASSERT_TRUE(r.ok());
    if (r->verdict == "no_significant_mismatch") {
      ++quiet;
      EXPECT_TRUE(r->findings.empty());
      EXPECT_NEAR(r->final_gap_val_um, r->baseline_gap_val_um, 0.5);
    } else {
      spurious += " seed " + std::to_string(seed) + ": " + r->findings[0].covariate;
    }
  }
  EXPECT_GE(quiet, num_seeds - std::max(1, num_seeds / 20))
      << "spurious findings:" << spurious;
}

// Every term's analytic parameter derivative matches central differences.
TEST(ModelTermTest, DerivativesMatchFiniteDifferences) {
  std::vector<ModelTerm> terms(9);
  terms[0].form = TermForm::kLogLinear;
  terms[0].params = {0.3};
  terms[0].center = 5;
  terms[0].scale = 2;
  terms[1].form = TermForm::kPower;
  terms[1].params = {-0.7};
  terms[1].center = 4;
  terms[2].form = TermForm::kSaturating;
  terms[2].params = {0.4, std::log(3.0)};
  terms[3].form = TermForm::kDecaying;
  terms[3].params = {0.8, std::log(2.0)};
  terms[4].form = TermForm::kFlag;
  terms[4].params = {-0.2};
  terms[5].form = TermForm::kBinned;
  terms[5].params = {0.1, 0.3};
  terms[5].edges = {2, 6};
  terms[6].form = TermForm::kPerLevel;
  terms[6].params = {0.2, -0.1};
  terms[6].num_levels = 3;
  terms[7].form = TermForm::kOffsetDecay;
  terms[7].params = {-40, std::log(6.0)};
  terms[8].form = TermForm::kOffsetLinear;
  terms[8].params = {5};
  terms[8].center = 1;
  terms[8].scale = 3;
  for (const ModelTerm& t : terms) {
    for (double z : {0.0, 1.0, 2.5, 7.0}) {
      const bool offset = t.IsMeasurementTerm();
      std::vector<double> g(t.NumParams());
      const double v0 = offset ? TermOffset(t, z, g.data()) : TermMultiplier(t, z, g.data());
      EXPECT_TRUE(std::isfinite(v0));
      for (int j = 0; j < t.NumParams(); ++j) {
        ModelTerm up = t, down = t;
        up.params[j] += 1e-6;
        down.params[j] -= 1e-6;
        const double fd = offset ? (TermOffset(up, z, nullptr) - TermOffset(down, z, nullptr)) / 2e-6
                                 : (TermMultiplier(up, z, nullptr) - TermMultiplier(down, z, nullptr)) / 2e-6;
        EXPECT_NEAR(g[j], fd, 1e-6 * std::max(1.0, std::abs(fd)))
            << TermFormName(t.form) << " z=" << z << " param " << j;
      }
    }
    // Nested: zero amplitude gives the baseline.
    ModelTerm zero = t;
    zero.params[0] = 0;
    if (t.form == TermForm::kBinned || t.form == TermForm::kPerLevel) {
      std::fill(zero.params.begin(), zero.params.end(), 0.0);
    }
    EXPECT_DOUBLE_EQ(t.IsMeasurementTerm() ? TermOffset(zero, 3.0, nullptr) + 1
                                           : TermMultiplier(zero, 3.0, nullptr),
                     1.0)
        << TermFormName(t.form);
  }
}

}  // namespace
}  // namespace rollwear
