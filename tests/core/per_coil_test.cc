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
#include "core/fit/term_model_internal.h"
#include "core/model/predictor.h"
#include "core/model/roll_factor_update.h"
#include "tests/core/extra_terms_util.h"
#include "tests/core/jacobian_check.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using extra_terms_test::BatchPrediction;
using extra_terms_test::ModelWithTerms;
using extra_terms_test::SpeedTerm;

ModelTerm PerCoilAt(int stand, double um_per_coil) {
  ModelTerm t;
  t.covariate = "campaign_coils_before";
  t.form = TermForm::kPerCoil;
  t.params = {um_per_coil};
  t.scope.stand = stand;
  return t;
}

// A roll-effect term over every roll of `td`: roll r's factor
// exp(0.3 sin(r)), levels in the fit data's order (as a fit keeps them).
ModelTerm RollEffectOf(const TermData& td) {
  ModelTerm t;
  t.covariate = kRollIdName;
  t.form = TermForm::kRollEffect;
  t.scale = 0.2;
  t.levels = td.catalog[td.CovariateIndex(kRollIdName)].levels;
  for (size_t r = 0; r < t.levels.size(); ++r)
    t.params.push_back(0.3 * std::sin(static_cast<double>(r + 1)));
  t.num_levels = static_cast<int>(t.levels.size());
  return t;
}

// The daemon's running wear coil by coil against the batch prediction,
// with wear per coil at F7 beside a multiplier (which does not scale it)
// and a roll's own factor (which does: r a per coil).
TEST(PerCoilTest, TheDaemonAddsEachCoilsWearAsTheBatchDoes) {
  const Simulation sim = simulator_test::Simulated(61, 16);
  const Dataset& d = sim.data;
  StatusOr<TermData> td = BuildTermData(d, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  ASSERT_GT(td->obs.size(), 40u);
  const ModelTerm speed = SpeedTerm();
  const ModelTerm roll = RollEffectOf(*td);
  const WearModel model = ModelWithTerms(*td, {PerCoilAt(7, 0.4), speed, roll});
  const WearModel without = ModelWithTerms(*td, {speed, roll});
  const std::vector<double> batch = BatchPrediction(*td, model, true);
  const std::vector<double> batch_without = BatchPrediction(*td, without, true);
  const DatasetIndex index(d);
  int at_f7 = 0;
  for (size_t o = 0; o < td->obs.size(); ++o) {
    const TermObservation& ob = td->obs[o];
    const Mount& mount = d.mounts[ob.mount];
    RollWearState st = MountRoll(
        model, RollPositionName(mount.stand, mount.position),
        d.roll_types[mount.roll_type], mount.diameter_mm, mount.hardness_hb,
        d.campaigns[ob.campaign].started_at, {}, {}, mount.roll_id);
    const std::vector<int>& passes = index.PassesOf(ob.campaign, mount.stand);
    for (int pi : passes) AddPass(model, PassInputOf(d, d.passes[pi]), &st);
    EXPECT_NEAR(st.wear_um, batch[o], 1e-9 * batch[o]) << "observation " << o;
    // r 0.4 µm for each coil at F7 (r the roll's factor), nothing at F6.
    const double r = std::exp(RollLogFactor(roll, mount.roll_id));
    const double added = mount.stand == 7 ? r * 0.4 * passes.size() : 0.0;
    EXPECT_NEAR(batch[o] - batch_without[o], added, 1e-9 * batch[o])
        << "observation " << o;
    at_f7 += mount.stand == 7 ? 1 : 0;
  }
  EXPECT_GT(at_f7, 0);
  EXPECT_LT(at_f7, static_cast<int>(td->obs.size()));
}

// The fits' Jacobian (core/fit/term_model_internal.h) with wear per coil
// beside a multiplier and a roll's own factor: every derivative, in log K
// and in every term's parameters, that of central finite differences.
TEST(PerCoilTest, TheFitsJacobianIsThatOfTheirPrediction) {
  const Simulation sim = simulator_test::Simulated(62, 12);
  StatusOr<TermData> td = BuildTermData(sim.data, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  std::vector<TermSpec> specs;
  const ModelTerm speed = SpeedTerm();
  for (const ModelTerm& t : {PerCoilAt(7, 0.4), speed, RollEffectOf(*td)}) {
    TermSpec s;
    s.term = t;
    s.covariate = td->CovariateIndex(t.covariate);
    ASSERT_GE(s.covariate, 0) << t.covariate;
    specs.push_back(s);
  }
  fit_internal::TermModel model(*td, specs);
  std::vector<double> x(model.num_params(), 0.0);
  for (int j = 0; j < model.num_coef(); ++j) x[j] = -1.0 + 0.01 * j;
  int off = model.num_coef();
  for (const TermSpec& s : specs) {
    for (double p : s.term.params) x[off++] = p;
  }
  const int checked = jacobian_check::ExpectJacobianOfPrediction(
                          &model, x, static_cast<int>(td->obs.size()), 7)
                          .nonzero;
  EXPECT_GT(checked, 20);
}

// Variant 0 wears both stands, variant 1 one stand (the truth's scope).
// Reduced under the sanitizers (150 campaigns, where the scorecard names it
// in 7 of 8 seeds; seeds 201 and 202 are among those named).
TEST(PerCoilTest, HiddenWearPerCoilIsNamedWhereItActsWithItsSize) {
  simulator_test::ForEachSingleFinding(
      {{"per_coil:0", 201}, {"per_coil:1", 202}},
      test_size::FullOr(kPaperCampaigns, 150),
      [](const std::string& effect, const SimulatedEffect& truth,
         const Finding& f) {
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
      });
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
  // The refused fit is no yardstick for the others: the true wear per coil
  // is never refused as its shadow.
  for (const RunnerUp& r : d.report.runners_up) {
    EXPECT_FALSE(r.form == "per_coil" &&
                 r.refusal == RefusalKind::kShadowOfRefused)
        << simulator_test::DescribeReport(d.report);
  }
}

// Wear per coil at one stand and a growth along the campaign at both: the
// round that adopts the growth, before wear per coil is in the model, sees
// it at one stand only ("elsewhere the wear law holds": false). The
// siblings guard on the final model withdraws it and locates it; wear per
// coil stays named. Seed 103 at 395 campaigns (named "growth at F6 only"
// before the final check), seed 109 at 150 under the sanitizers (the same
// at F7).
TEST(PerCoilTest, AScopeTheFinalModelDoesNotConfineIsWithdrawn) {
  const bool full = !test_size::kSanitized;
  const simulator_test::Diagnosed d = simulator_test::DiagnoseSimulated(
      full ? 103 : 109, {"per_coil:1", "campaign_growth"}, full ? 395 : 150);
  const std::string report = simulator_test::DescribeReport(d.report);
  for (const Finding& f : d.report.findings) {
    // Neither a growth confined to one stand nor anything but wear per coil.
    EXPECT_EQ(f.form, "per_coil") << report;
  }
  ASSERT_EQ(d.report.findings.size(), 1u) << report;
  EXPECT_EQ(d.report.findings[0].scope, d.sim.truth.effects[1].scope);
  int withdrawn = 0;
  for (const RunnerUp& r : d.report.runners_up) {
    if (r.reason.rfind("withdrawn on the final model", 0) != 0) continue;
    ++withdrawn;
    EXPECT_EQ(r.refusal, RefusalKind::kProxyGuard);
    EXPECT_EQ(r.guard, "siblings");
    EXPECT_EQ(r.covariate, "campaign_length_before_m");
    EXPECT_EQ(r.round, 0);
  }
  EXPECT_EQ(withdrawn, 1) << report;
  bool located = false;
  for (const Unexplained& u : d.report.unexplained)
    located = located || u.dimension == "effect_by_stand";
  EXPECT_TRUE(located) << report;
}

}  // namespace
}  // namespace rollwear
