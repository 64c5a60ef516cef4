// Scoped, cell and measurement per-level terms (model_terms.h): the daemon's
// coil-by-coil prediction equals the batch fit's, and the diagnosis names a
// grinder offset and a roll type x stand cell on modified simulated data.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/pass_input.h"
#include "core/diagnosis/diagnosis.h"
#include "core/fit/term_fit.h"
#include "core/fit/term_refit.h"
#include "core/model/aggregation.h"
#include "core/model/predictor.h"
#include "core/model/wear_law.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

constexpr int kCampaigns = test_size::FullOr(395, 200);
// The paper's size, also under the sanitizers: at 200 campaigns the
// roll-type cell of NamesRollTypeAtStandCell lost to a continuous proxy
// (`reduction` in the session-9 ASan run). Since session 10 the proxy guard
// compares a winner with the round's cells and the scorecard names the cell
// at 200 campaigns too (docs/diagnosis.md, Limits); the size was kept
// because this test's own data were not re-checked at 200.

Simulation Clean(uint64_t seed, int campaigns) {
  return simulator_test::Simulated(seed, campaigns);
}

TEST(ScopedTermTest, CellAndOffsetDerivativesMatchFiniteDifferences) {
  ModelTerm cell;
  cell.form = TermForm::kCell;
  cell.params = {0.25};
  double g = 0;
  const double m = TermMultiplier(cell, 1.0, &g);
  EXPECT_NEAR(m, std::exp(0.25), 1e-12);
  EXPECT_NEAR(g, std::exp(0.25), 1e-12);
  ModelTerm off;
  off.form = TermForm::kOffsetPerLevel;
  off.num_levels = 3;
  off.reference_level = 1;
  off.params = {-15, 7};
  double grad[2];
  EXPECT_EQ(TermOffset(off, 1.0, grad), 0.0);  // the reference reads as is
  EXPECT_EQ(TermOffset(off, 0.0, grad), -15.0);
  EXPECT_EQ(grad[0], 1.0);
  EXPECT_EQ(TermOffset(off, 2.0, grad), 7.0);
  EXPECT_EQ(grad[1], 1.0);
  EXPECT_EQ(grad[0], 0.0);
}

// A model with a stand-scoped, a grade-scoped and a cell term predicts coil
// by coil (predictor.h) what the batch term fit predicts (1e-9 relative).
TEST(ScopedTermTest, ScopedModelPredictsCoilByCoilAsInBatch) {
  const Simulation sim = Clean(21, 60);
  const Dataset& d = sim.data;
  ModelTerm temp;
  temp.covariate = "temperature_c";
  temp.form = TermForm::kLogLinear;
  temp.params = {-0.2};
  temp.center = 950;
  temp.scale = 40;
  temp.scope.stand = 7;
  ModelTerm lub;
  lub.covariate = "lubrication";
  lub.form = TermForm::kFlag;
  lub.params = {-0.1};
  lub.scope.grade = d.grades.front();
  ModelTerm cell;
  cell.covariate = kCellCovariateName;
  cell.form = TermForm::kCell;
  cell.params = {0.2};
  cell.scope.stand = 6;
  cell.scope.roll_type = d.roll_types.front();
  std::vector<int> train;
  for (int c = 0; c < static_cast<int>(d.campaigns.size()); ++c) train.push_back(c);
  StatusOr<WearModel> m = RefitWithTerms(d, WearLaw::kWang, {temp, lub, cell}, train);
  ASSERT_TRUE(m.ok()) << m.status().ToString();
  ASSERT_EQ(m->terms.size(), 3u);
  EXPECT_EQ(m->terms[0].scope.stand, 7);
  EXPECT_EQ(m->terms[2].scope.roll_type, d.roll_types.front());

  StatusOr<TermData> td = BuildTermData(d, WearLaw::kWang);
  ASSERT_TRUE(td.ok());
  std::vector<TermSpec> specs;
  for (const ModelTerm& t : m->terms) {
    TermSpec s;
    s.term = t;
    s.covariate = td->CovariateIndex(t.covariate);
    specs.push_back(s);
  }
  std::vector<double> log_k;
  for (double k : m->k) log_k.push_back(std::log(k));
  std::vector<int> all(td->obs.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const std::vector<double> batch = PredictTerms(*td, all, log_k, specs, true);
  // Unscoped, the same terms predict differently (the scope matters).
  std::vector<TermSpec> unscoped = specs;
  for (TermSpec& s : unscoped) s.term.scope = TermScope{};
  const std::vector<double> everywhere = PredictTerms(*td, all, log_k, unscoped, true);
  const DatasetIndex index(d);
  int checked = 0, differ = 0;
  for (size_t o = 0; o < td->obs.size(); ++o) {
    const TermObservation& ob = td->obs[o];
    const Mount& mount = d.mounts[ob.mount];
    RollWearState state = MountRoll(*m, RollPositionName(mount.stand, mount.position),
                                    d.roll_types[mount.roll_type], mount.diameter_mm,
                                    mount.hardness_hb, d.campaigns[ob.campaign].started_at);
    for (int pi : index.PassesOf(ob.campaign, mount.stand)) {
      AddPass(*m, PassInputOf(d, d.passes[pi]), &state);
    }
    EXPECT_NEAR(state.wear_um, batch[o], 1e-9 * batch[o]);
    differ += std::abs(everywhere[o] - batch[o]) > 1e-6 * batch[o] ? 1 : 0;
    ++checked;
  }
  EXPECT_GT(checked, 200);  // 60 campaigns x 4 measured rolls
  EXPECT_GT(differ, checked / 2);
}

// Mean |measured - noise-free| over the report's validation readings, the
// noise-free wear from the simulator's truth with the test's modification
// (`truth`, aligned with the measurements).
double NoiseFloor(const Dataset& d, const std::vector<double>& truth,
                  const DiagnosisReport& r) {
  std::map<std::tuple<std::string, int, int>, double> noise_free;
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    noise_free[{d.campaigns[m.campaign].id, m.stand, static_cast<int>(m.position)}] = truth[i];
  }
  double sum = 0;
  int n = 0;
  for (const DiagnosisPoint& p : r.points) {
    if (!p.validation) continue;
    sum += std::abs(p.measured_um -
                    noise_free.at({p.campaign_id, p.stand, static_cast<int>(p.position)}));
    ++n;
  }
  return sum / std::max(1, n);
}

// Adds a measurement text column "grinder": level B on ~30 % of readings
// reads `offset_um` lower.
void AddGrinder(double offset_um, Simulation* sim) {
  ExtraColumns& e = sim->data.measurement_extra;
  e.factor_names.push_back("grinder");
  e.factor_levels.push_back({"A", "B"});
  std::vector<int> codes;
  for (size_t i = 0; i < sim->data.measurements.size(); ++i) {
    const bool b = (i * 7919) % 10 < 3;
    codes.push_back(b ? 1 : 0);
    if (b) {
      sim->data.measurements[i].wear_center_um += offset_um;
      sim->truth.noise_free_wear_um[i] += offset_um;
    }
  }
  e.factor.push_back(codes);
}

// At the paper's size the data identify which grinder reads true (the wear
// law has no intercept; docs/diagnosis.md, "Which gauge reads true"): B is
// named. At the sanitizers' 200 campaigns they do not (the two references'
// fits differ by a likelihood-ratio 0.3): the offset is stated between the
// levels, and neither level is named. Either way A is never named, and the
// offset between the levels is the simulated one.
TEST(ScopedTermTest, NamesGrinderOffset) {
  Simulation sim = Clean(31, kCampaigns);
  AddGrinder(-15.0, &sim);
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_FALSE(r->findings.empty());
  const Finding& f = r->findings.front();
  EXPECT_EQ(f.covariate, "grinder");
  EXPECT_EQ(f.form, "offset_per_level");
  EXPECT_TRUE(f.scope.empty());
  auto offset = [&](const std::string& level) {
    auto it = f.parameters.find("offset_um[" + level + "]");
    return it == f.parameters.end() ? 0.0 : it->second;  // the reference reads 0
  };
  EXPECT_NEAR(offset("B") - offset("A"), -15.0, 3.0) << f.explanation;
  if (test_size::kSanitized) {
    EXPECT_EQ(f.shape, "offset_between_levels") << f.explanation;
    EXPECT_TRUE(f.levels.empty()) << f.explanation;
    EXPECT_NE(f.explanation.find("reads true is not identified"), std::string::npos)
        << f.explanation;
  } else {
    EXPECT_EQ(f.shape, "offset_per_level") << f.explanation;
    EXPECT_EQ(f.levels, std::vector<std::string>{"B"});
    EXPECT_NE(f.explanation.find("grinder=B is offset by -1"), std::string::npos)
        << f.explanation;
  }
  EXPECT_EQ(r->findings.size(), 1u);
  EXPECT_LE(r->final_gap_val_um,
            1.10 * NoiseFloor(sim.data, sim.truth.noise_free_wear_um, *r));
}

// Rolls of one type wear 1.3x at F7 only: a cell finding on roll_type with
// scope F7, not hardness or contact length.
TEST(ScopedTermTest, NamesRollTypeAtStandCell) {
  Simulation sim = Clean(41, kPaperCampaigns);
  Dataset& d = sim.data;
  const DatasetIndex index(d);
  // A roll type that runs at F6 and F7 (a type only at F7 is a roll-type
  // effect the K structure has), less often at F7: with two stands,
  // "x1.3 at F7" and "x1/1.3 at F6" describe the same data (the type's kR
  // absorbs the rest), and the engine names the smaller cell, the exception
  // (diagnosis_scoped.cc).
  std::map<int, std::map<int, int>> mounts;  // type -> stand -> count
  for (const Mount& m : d.mounts) ++mounts[m.roll_type][m.stand];
  int type = -1, best = 0;
  for (auto& [t, by_stand] : mounts) {
    const int both = std::min(by_stand[6], by_stand[7]);
    if (both > best && by_stand[7] < by_stand[6]) {
      best = both;
      type = t;
    }
  }
  ASSERT_GE(type, 0);
  int changed = 0;
  for (Measurement& m : d.measurements) {
    if (m.stand != 7) continue;
    const int mi = index.MountOf(m.campaign, RollPositionSlot(m.stand, m.position));
    if (mi < 0 || d.mounts[mi].roll_type != type) continue;
    m.wear_center_um *= 1.3;
    sim.truth.noise_free_wear_um[&m - d.measurements.data()] *= 1.3;
    ++changed;
  }
  ASSERT_GT(changed, 30);
  StatusOr<DiagnosisReport> r = Diagnose(d, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_FALSE(r->findings.empty());
  const Finding& f = r->findings.front();
  EXPECT_EQ(f.covariate, "roll_type") << f.mechanism;
  EXPECT_EQ(f.levels, std::vector<std::string>{d.roll_types[type]});
  EXPECT_EQ(f.scope, (std::map<std::string, std::string>{{"stand", "F7"}}));
  EXPECT_NEAR(f.parameters.at("multiplier"), 1.3, 0.06);
  EXPECT_EQ(r->findings.size(), 1u);
  EXPECT_LE(r->final_gap_val_um, 1.10 * NoiseFloor(d, sim.truth.noise_free_wear_um, *r));
}

// Colder strip wears F7 more, and F7 only: m = exp(-0.25 (T - c) / s) per
// pass at F7 (c, s: mean and sd of the F7 temperatures), applied to the
// clean simulation's noise-free wear through the per-pass true K x load
// weights (the roll's scatter factor cancels in the ratio). One finding on
// temperature_c scoped to F7, no second spurious one.
TEST(ScopedTermTest, NamesTemperatureAtF7Only) {
  Simulation sim = Clean(51, kCampaigns);
  Dataset& d = sim.data;
  const DatasetIndex index(d);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (const Pass& p : d.passes) {
    if (p.stand != 7) continue;
    sum += p.temperature_c;
    sum2 += p.temperature_c * p.temperature_c;
    ++n;
  }
  ASSERT_GT(n, 100);
  const double c = sum / n, s = std::sqrt(sum2 / n - c * c);
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    Measurement& m = d.measurements[i];
    if (m.stand != 7) continue;
    const int mi = index.MountOf(m.campaign, RollPositionSlot(m.stand, m.position));
    ASSERT_GE(mi, 0);
    double base = 0, with = 0;
    for (int pi : index.PassesOf(m.campaign, 7)) {
      const Pass& p = d.passes[pi];
      const double w = sim.truth.k_grade.at(d.grades[p.grade]) *
                       BaseLoad(WearLaw::kWang, MakeLoadInput(p, d.mounts[mi]));
      base += w;
      with += w * std::exp(-0.25 * (p.temperature_c - c) / s);
    }
    const double nf = sim.truth.noise_free_wear_um[i];
    const double shifted = nf * with / base;
    m.wear_center_um += shifted - nf;
    sim.truth.noise_free_wear_um[i] = shifted;
  }
  StatusOr<DiagnosisReport> r = Diagnose(d, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_FALSE(r->findings.empty());
  const Finding& f = r->findings.front();
  EXPECT_EQ(f.covariate, "temperature_c") << f.mechanism;
  EXPECT_EQ(f.scope, (std::map<std::string, std::string>{{"stand", "F7"}}));
  EXPECT_EQ(f.mechanism, "cold_strip_hardness_and_scale");
  EXPECT_NE(f.explanation.find("only to F7"), std::string::npos) << f.explanation;
  EXPECT_NE(f.explanation.find("°C"), std::string::npos) << f.explanation;
  EXPECT_EQ(r->findings.size(), 1u);
  EXPECT_LE(r->final_gap_val_um, 1.10 * NoiseFloor(d, sim.truth.noise_free_wear_um, *r));
}

}  // namespace
}  // namespace rollwear
