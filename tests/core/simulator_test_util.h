// Helpers shared by the simulator tests: running the simulator (and the
// diagnosis on its data), and each
// measurement seen through its rows (the baseline wear recomputed from the
// true factors with Wang's law, and covariates weighted by baseline wear).
//
// Thread-safety: plain functions over values.
#ifndef ROLLWEAR_TESTS_CORE_SIMULATOR_TEST_UTIL_H_
#define ROLLWEAR_TESTS_CORE_SIMULATOR_TEST_UTIL_H_

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis.h"
#include "core/model/wear_law.h"
#include "core/sim/simulator.h"
#include "tests/core/test_size.h"

namespace rollwear::simulator_test {

// `roll_factor_sd`: SimulatorOptions::roll_wear_factor_sd (each physical
// roll's lifelong wear factor; 0: none).
inline Simulation Simulated(uint64_t seed, int campaigns,
                            std::vector<std::string> effects = {},
                            double missing = 0, double roll_factor_sd = 0) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  o.effects = std::move(effects);
  o.missing_measurement_fraction = missing;
  o.roll_wear_factor_sd = roll_factor_sd;
  StatusOr<Simulation> s = Simulate(o);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return std::move(s).value();
}

// A simulated mill and its diagnosis with the default options.
struct Diagnosed {
  Simulation sim;
  DiagnosisReport report;
};
inline Diagnosed DiagnoseSimulated(uint64_t seed,
                                   std::vector<std::string> effects,
                                   int campaigns = kPaperCampaigns) {
  Diagnosed d;
  d.sim = Simulated(seed, campaigns, std::move(effects));
  StatusOr<DiagnosisReport> r = Diagnose(d.sim.data, DiagnosisOptions{});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  if (r.ok()) d.report = std::move(r).value();
  return d;
}

// Mounts by (campaign, stand, position) and passes by (campaign, stand).
inline std::map<std::tuple<int, int, int>, const Mount*> MountsByKey(
    const Dataset& d) {
  std::map<std::tuple<int, int, int>, const Mount*> mounts;
  for (const Mount& m : d.mounts) {
    mounts[{m.campaign, m.stand, static_cast<int>(m.position)}] = &m;
  }
  return mounts;
}
inline std::map<std::pair<int, int>, std::vector<const Pass*>> PassesByStand(
    const Dataset& d) {
  std::map<std::pair<int, int>, std::vector<const Pass*>> passes;
  for (const Pass& p : d.passes) passes[{p.campaign, p.stand}].push_back(&p);
  return passes;
}

// One measurement with its baseline wear (no effect), recomputed here from
// the true factors (Wang's law, option 1), and the
// covariates of its passes, weighted by their baseline wear increments.
struct MeasurementView {
  double measured = 0, noise_free = 0, baseline = 0;
  double stand_length_m = 0;  // sum of length_m of the campaign at the stand
  double mean_temperature_c = 0, mean_log_speed = 0, lubricated_share = 0;
  double hardness_hb = 0, cooling_h = 0;
  bool any_lubricated = false;
};

inline std::vector<MeasurementView> Views(const Simulation& sim) {
  const Dataset& d = sim.data;
  const SimulationTruth& t = sim.truth;
  const auto mounts = MountsByKey(d);
  const auto passes = PassesByStand(d);

  std::vector<MeasurementView> out;
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    const Mount& mount =
        *mounts.at({m.campaign, m.stand, static_cast<int>(m.position)});
    const double kf = t.k_position.at(RollPositionName(m.stand, m.position));
    const double kr = t.k_roll_type.at(d.roll_types[mount.roll_type]);
    MeasurementView v;
    v.measured = m.wear_center_um;
    v.noise_free = t.noise_free_wear_um[i];
    v.hardness_hb = mount.hardness_hb;
    v.cooling_h = (m.measured_at - d.campaigns[m.campaign].ended_at) / 3600.0;
    for (const Pass* p : passes.at({m.campaign, m.stand})) {
      const PassLoadInput in{p->force_kn,          p->width_mm,
                             p->length_m,          p->entry_thickness_mm,
                             p->exit_thickness_mm, mount.diameter_mm,
                             mount.hardness_hb};
      // Baseline wear increment K * Load; covariates are weighted by it.
      const double dw = kf * kr * t.k_grade.at(d.grades[p->grade]) *
                        BaseLoad(WearLaw::kWang, in);
      v.baseline += dw;
      v.stand_length_m += p->length_m;
      v.mean_temperature_c += dw * p->temperature_c;
      v.mean_log_speed += dw * std::log(p->speed_mps);
      v.lubricated_share += dw * (p->lubrication ? 1 : 0);
      v.any_lubricated = v.any_lubricated || p->lubrication;
    }
    v.mean_temperature_c /= v.baseline;
    v.mean_log_speed /= v.baseline;
    v.lubricated_share /= v.baseline;
    out.push_back(v);
  }
  return out;
}

// A diagnosis report in one line, for test failure messages.
inline std::string DescribeReport(const DiagnosisReport& r) {
  std::string s = "verdict " + r.verdict + ";";
  for (const Finding& f : r.findings)
    s += " finding " + f.covariate + " (" + f.form + ");";
  for (const RunnerUp& u : r.runners_up)
    s += " runner-up " + u.covariate + ": " + u.reason + ";";
  for (const Unexplained& u : r.unexplained) {
    char buf[256];
    std::snprintf(
        buf, sizeof(buf), " unexplained %s at %s: %+.1f um, p_adj %.2g;",
        u.dimension.c_str(), u.where.c_str(), u.mean_residual_um, u.p_adjusted);
    s += buf;
  }
  return s;
}

inline double Correlation(const std::vector<double>& x,
                          const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxy / std::sqrt(sxx * syy);
}

// Ratio noise-free / baseline and a covariate of every measurement.
template <typename F>
void RatioAgainst(const std::vector<MeasurementView>& views, F covariate,
                  std::vector<double>* ratio, std::vector<double>* x) {
  for (const MeasurementView& v : views) {
    ratio->push_back(v.noise_free / v.baseline);
    x->push_back(covariate(v));
  }
}

// Diagnoses each simulated (effect, seed) at `campaigns` campaigns, asserts
// one hidden effect and exactly one finding, and calls
// check(effect, truth, finding) on them.
template <typename Check>
void ForEachSingleFinding(
    std::initializer_list<std::pair<const char*, uint64_t>> cases,
    int campaigns, Check check) {
  for (const auto& [effect, seed] : cases) {
    const Diagnosed d = DiagnoseSimulated(seed, {effect}, campaigns);
    ASSERT_EQ(d.sim.truth.effects.size(), 1u) << effect;
    ASSERT_EQ(d.report.findings.size(), 1u)
        << effect << DescribeReport(d.report);
    check(std::string(effect), d.sim.truth.effects[0], d.report.findings[0]);
  }
}

}  // namespace rollwear::simulator_test

#endif  // ROLLWEAR_TESTS_CORE_SIMULATOR_TEST_UTIL_H_
