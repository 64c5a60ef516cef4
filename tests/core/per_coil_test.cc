// Wear per coil (the per_coil family, core/model/term_family_per_coil.cc):
// the daemon's predictor adds a on every pass of the rolls the term covers,
// coil by coil, exactly as the diagnosis engine's batch prediction does; and
// on a simulated mill whose coils each add wear whatever their length (the
// simulator's per_coil family, hidden), the diagnosis names wear per coil at
// the right stand with its size, not a growth along the campaign or a load
// dependence.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/pass_input.h"
#include "core/model/predictor.h"
#include "tests/core/extra_terms_util.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using extra_terms_test::BatchPrediction;
using extra_terms_test::ModelWithTerms;

ModelTerm PerCoilAt(int stand, double um_per_coil) {
  ModelTerm t;
  t.covariate = "campaign_coils_before";
  t.form = TermForm::kPerCoil;
  t.params = {um_per_coil};
  t.scope.stand = stand;
  return t;
}

TEST(PerCoilTest, TheDaemonAddsEachCoilsWearAsTheBatchDoes) {
  const Simulation sim = simulator_test::Simulated(61, 16);
  const Dataset& d = sim.data;
  StatusOr<TermData> td = BuildTermData(d, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  ASSERT_GT(td->obs.size(), 40u);
  ModelTerm speed;  // a multiplier beside it: the wear per coil is not scaled
  speed.covariate = "speed_mps";
  speed.form = TermForm::kLogLinear;
  speed.params = {0.2};
  speed.center = 10;
  speed.scale = 2;
  const WearModel model = ModelWithTerms(*td, {PerCoilAt(7, 0.4), speed});
  const WearModel without = ModelWithTerms(*td, {speed});
  const std::vector<double> batch = BatchPrediction(*td, model, true);
  const std::vector<double> batch_without = BatchPrediction(*td, without, true);
  const DatasetIndex index(d);
  int at_f7 = 0;
  for (size_t o = 0; o < td->obs.size(); ++o) {
    const TermObservation& ob = td->obs[o];
    const Mount& mount = d.mounts[ob.mount];
    RollWearState st =
        MountRoll(model, RollPositionName(mount.stand, mount.position),
                  d.roll_types[mount.roll_type], mount.diameter_mm,
                  mount.hardness_hb, d.campaigns[ob.campaign].started_at);
    const std::vector<int>& passes = index.PassesOf(ob.campaign, mount.stand);
    for (int pi : passes) AddPass(model, PassInputOf(d, d.passes[pi]), &st);
    EXPECT_NEAR(st.wear_um, batch[o], 1e-9 * batch[o]) << "observation " << o;
    // 0.4 µm for each coil at F7, nothing at F6.
    const double added = mount.stand == 7 ? 0.4 * passes.size() : 0.0;
    EXPECT_NEAR(batch[o] - batch_without[o], added, 1e-9 * batch[o])
        << "observation " << o;
    at_f7 += mount.stand == 7 ? 1 : 0;
  }
  EXPECT_GT(at_f7, 0);
  EXPECT_LT(at_f7, static_cast<int>(td->obs.size()));
}

// Variant 0 wears both stands, variant 1 one stand (the truth's scope).
// Reduced under the sanitizers (150 campaigns, where the scorecard names it
// in 7 of 8 seeds; seeds 201 and 202 are among those named).
TEST(PerCoilTest, HiddenWearPerCoilIsNamedWhereItActsWithItsSize) {
  const int campaigns = test_size::FullOr(kPaperCampaigns, 150);
  for (const auto& [effect, seed] :
       {std::pair<const char*, uint64_t>{"per_coil:0", 201},
        std::pair<const char*, uint64_t>{"per_coil:1", 202}}) {
    const simulator_test::Diagnosed d =
        simulator_test::DiagnoseSimulated(seed, {effect}, campaigns);
    ASSERT_EQ(d.sim.truth.effects.size(), 1u);
    const SimulatedEffect& truth = d.sim.truth.effects[0];
    ASSERT_EQ(d.report.findings.size(), 1u)
        << effect << simulator_test::DescribeReport(d.report);
    const Finding& f = d.report.findings[0];
    EXPECT_EQ(f.form, "per_coil") << effect;
    EXPECT_EQ(f.mechanism, "wear_per_coil") << effect;
    EXPECT_TRUE(f.carriers.empty()) << effect;
    EXPECT_EQ(f.scope, truth.scope) << effect;
    // The size within 3 standard errors and 25 % of the truth.
    const double a = f.parameters.at("um_per_coil");
    const double se = f.parameter_std_errors.at("param0");
    const double want = truth.parameters.at("um_per_coil");
    EXPECT_NEAR(a, want, 3 * se) << effect;
    EXPECT_NEAR(a, want, 0.25 * want) << effect;
    EXPECT_LT(f.gap_val_after_um, f.gap_val_before_um) << effect;
  }
}

// Wear per coil everywhere and a run-in together (seed 102): a reading
// offset fading over the months fits them best with its amplitude at the
// box's 1000 µm, a constant offset standing in for wear each campaign adds.
// Named before the at_box_bound check (p = 7e-61, "the grinder's reading
// drifts"); now refused, and where the mismatch lives is said instead.
TEST(PerCoilTest, AFitStoppedAtItsBoxEdgeIsLocatedNotNamed) {
  const int campaigns = test_size::FullOr(kPaperCampaigns, 150);
  const simulator_test::Diagnosed d = simulator_test::DiagnoseSimulated(
      102, {"per_coil:0", "run_in"}, campaigns);
  for (const Finding& f : d.report.findings) {
    EXPECT_NE(f.covariate, "measured_at")
        << simulator_test::DescribeReport(d.report);
  }
  bool refused = false;
  for (const RunnerUp& r : d.report.runners_up) {
    if (r.refusal != RefusalKind::kAtBoxBound) continue;
    refused =
        refused || (r.covariate == "measured_at" && r.form == "offset_decay" &&
                    r.reason.find("bound 1000") != std::string::npos);
  }
  EXPECT_TRUE(refused) << simulator_test::DescribeReport(d.report);
  EXPECT_FALSE(d.report.unexplained.empty());
}

}  // namespace
}  // namespace rollwear
