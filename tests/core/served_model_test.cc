// The models the daemon can serve, evaluated the one way promotion uses
// (core/model/model_eval.h): coil by coil through the incremental predictor.
//  - a classical model: the same figures as the batch evaluation;
//  - a diagnosis's adopted model (wear-rate and measurement terms): the same
//    predictions as the diagnosis engine's own, and a refit of its terms
//    (core/fit/term_refit.h) keeps the gain on held-out campaigns;
//  - the recurrent network: the same predictions as its training-time
//    batch forward pass, and an interval that covers held-out measurements.
#include <cmath>
#include <map>
#include <tuple>

#include <gtest/gtest.h>

#include "core/model/aggregation.h"
#include "core/ann/ann_data.h"
#include "core/ann/ann_bptt.h"
#include "core/ann/ann_study.h"
#include "core/diagnosis/diagnosis.h"
#include "core/model/metrics.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "core/sim/simulator.h"
#include "core/fit/study.h"
#include "core/fit/term_refit.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

Simulation Mill(uint64_t seed, int campaigns, std::vector<std::string> effects = {}) {
  return simulator_test::Simulated(seed, campaigns, std::move(effects));
}

struct Split {
  DatasetIndex index;
  WearStatistics stats;
  CampaignSplit split;
  explicit Split(const Dataset& d)
      : index(d),
        stats(*Aggregate(d, index, WearLaw::kWang)),
        split(SplitCampaigns(stats, 2.0 / 3.0, kDefaultSplitSeed)) {}
};

TEST(ModelEvalTest, ClassicalCoilByCoilEqualsBatchEvaluation) {
  const Simulation sim = Mill(41, 60);
  const Split s(sim.data);
  StatusOr<SplitCalibration> run =
      CalibrateOnSplit(s.stats, s.split, CalibrationOptions{});
  ASSERT_TRUE(run.ok());
  const std::vector<MeasuredPrediction> p =
      PredictMeasured(run->result.model, sim.data, s.index, s.split.validation);
  const FitMetrics m = MetricsOfPredictions(p);
  EXPECT_EQ(m.n, run->validation.n);
  EXPECT_NEAR(m.gap_um, run->validation.gap_um, 1e-9 * run->validation.gap_um);
  EXPECT_NEAR(m.cost, run->validation.cost, 1e-9 * run->validation.cost);
  for (const MeasuredPrediction& x : p) {
    EXPECT_EQ(x.expected_um, x.wear_um);  // no measurement terms
    EXPECT_EQ(x.measured_um,
              sim.data.measurements[x.measurement].wear_center_um);
  }
}

// The diagnosis's adopted model, run coil by coil, reproduces the engine's
// own predictions of every measured roll (after_um), measurement terms
// included, and its validation gap.
void ExpectAdoptedModelReproducesDiagnosis(const Simulation& sim,
                                           const char* form_kind) {
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->verdict, "missing_physics_found");
  bool has_measurement_term = false;
  for (const ModelTerm& t : r->adopted_model.terms) {
    has_measurement_term |= t.IsMeasurementTerm();
  }
  EXPECT_EQ(has_measurement_term, std::string(form_kind) == "measurement");
  const Split s(sim.data);
  std::vector<int> all(sim.data.campaigns.size());
  for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
  std::map<std::tuple<std::string, int, int>, double> after;
  for (const DiagnosisPoint& p : r->points) {
    after[{p.campaign_id, p.stand, static_cast<int>(p.position)}] = p.after_um;
  }
  int checked = 0;
  for (const MeasuredPrediction& x :
       PredictMeasured(r->adopted_model, sim.data, s.index, all)) {
    auto it = after.find(
        {sim.data.campaigns[x.campaign].id, SlotStand(x.slot), x.slot % 2});
    ASSERT_NE(it, after.end());
    EXPECT_NEAR(x.expected_um, it->second, 1e-8 * std::max(1.0, it->second));
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(r->points.size()));
  const FitMetrics val = MetricsOfPredictions(
      PredictMeasured(r->adopted_model, sim.data, s.index, s.split.validation));
  EXPECT_NEAR(val.gap_um, r->final_gap_val_um, 1e-8 * r->final_gap_val_um);

  // Refit of the adopted terms from a perturbed start (amplitudes halved):
  // the recalibration a nightly run does once the terms are adopted. It
  // lands on the diagnosis's fit (validation gap within 2 %) and keeps
  // the gain over the baseline.
  std::vector<ModelTerm> start = r->adopted_model.terms;
  for (ModelTerm& t : start) t.params[0] *= 0.5;
  StatusOr<WearModel> refit =
      RefitWithTerms(sim.data, WearLaw::kWang, start, s.split.train);
  ASSERT_TRUE(refit.ok()) << refit.status().ToString();
  const FitMetrics refit_val = MetricsOfPredictions(
      PredictMeasured(*refit, sim.data, s.index, s.split.validation));
  ::testing::Test::RecordProperty("diagnosis_val_um",
                                  std::to_string(r->final_gap_val_um));
  ::testing::Test::RecordProperty("refit_val_um",
                                  std::to_string(refit_val.gap_um));
  EXPECT_NEAR(refit_val.gap_um, r->final_gap_val_um,
              0.02 * r->final_gap_val_um);
  EXPECT_LT(refit_val.gap_um, 0.95 * r->baseline_gap_val_um);
  EXPECT_GT(refit->noise_sd_um + refit->noise_rel, 0);
}

TEST(ModelEvalTest, AdoptedWearRateTermRunsCoilByCoilAndRefits) {
  ExpectAdoptedModelReproducesDiagnosis(Mill(7, 395, {"campaign_growth"}),
                                        "wear");
}

TEST(ModelEvalTest, AdoptedMeasurementTermRunsCoilByCoilAndRefits) {
  ExpectAdoptedModelReproducesDiagnosis(Mill(8, 395, {"warm_measurement"}),
                                        "measurement");
}

TEST(TermRefitTest, UnknownCovariateOrWrongParameterCountIsRefused) {
  const Simulation sim = Mill(42, 20);
  const Split s(sim.data);
  ModelTerm t;
  t.covariate = "no_such_column";
  t.form = TermForm::kLogLinear;
  t.params = {0.1};
  StatusOr<WearModel> r =
      RefitWithTerms(sim.data, WearLaw::kWang, {t}, s.split.train);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(r.status().message().find("no_such_column"), std::string::npos);
  // An offset on the measured value needs a measurement-side covariate.
  t.covariate = "force_kn";
  t.form = TermForm::kOffsetLinear;
  r = RefitWithTerms(sim.data, WearLaw::kWang, {t}, s.split.train);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("wear-rate covariate"), std::string::npos)
      << r.status().message();
  t.form = TermForm::kSaturating;  // needs 2 parameters
  r = RefitWithTerms(sim.data, WearLaw::kWang, {t}, s.split.train);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("expected 2"), std::string::npos);
}

// Under the sanitizers (test_size.h) 80 campaigns and 30 epochs instead of
// 120 and 60: 45 s under ASan in session 16, a third of it now (Release:
// 3.3 s -> 1.1 s); the same assertions hold there (seeds 43-45 checked).
TEST(ServedAnnTest, NetworkServedCoilByCoilEqualsBatchAndItsIntervalCovers) {
  const Simulation sim =
      Mill(43, test_size::FullOr(120, 80), {"campaign_growth"});
  const Split s(sim.data);
  AnnTrainingOptions o;
  o.members = 3;
  o.max_epochs = test_size::FullOr(60, 30);
  StatusOr<WearModel> m = TrainServableAnn(sim.data, s.split.train, o);
  ASSERT_TRUE(m.ok()) << m.status().ToString();
  ASSERT_TRUE(m->is_ann());
  EXPECT_EQ(m->ann->members.size(), 3u);
  EXPECT_GT(m->noise_sd_um + m->noise_rel, 0);

  // Batch forward pass of the trained network on the same sequences.
  const AnnInputs inputs = BuildAnnInputs(*m->ann, sim.data, s.index, s.stats);
  const std::vector<int> val_obs =
      s.stats.MeasuredObservations(s.split.validation);
  const std::vector<double> batch = PredictAnn(*m->ann, inputs, val_obs);
  const std::vector<MeasuredPrediction> p =
      PredictMeasured(*m, sim.data, s.index, s.split.validation);
  ASSERT_EQ(p.size(), batch.size());
  std::map<std::pair<int, int>, double> by_roll;
  for (size_t k = 0; k < val_obs.size(); ++k) {
    const Observation& ob = s.stats.observations[val_obs[k]];
    by_roll[{ob.campaign, ob.slot}] = batch[k];
  }
  int covered = 0;
  for (const MeasuredPrediction& x : p) {
    const double b = by_roll.at({x.campaign, x.slot});
    EXPECT_NEAR(x.wear_um, b, 1e-9 * b);
    // Interval of the same roll, rebuilt through the predictor.
    const int mi = s.index.MountOf(x.campaign, x.slot);
    const Mount& mount = sim.data.mounts[mi];
    RollWearState st =
        MountRoll(*m, RollPositionName(mount.stand, mount.position),
                  sim.data.roll_types[mount.roll_type], mount.diameter_mm,
                  mount.hardness_hb);
    for (int pi : s.index.PassesOf(x.campaign, mount.stand)) {
      AddPass(*m, PassInputOf(sim.data, sim.data.passes[pi]), &st);
    }
    EXPECT_NEAR(st.wear_um, b, 1e-9 * b);
    const auto [lo, hi] = WearInterval(*m, st);
    EXPECT_LT(lo, st.wear_um);
    EXPECT_GT(hi, st.wear_um);
    covered += x.measured_um >= lo && x.measured_um <= hi;
  }
  // A 95 % interval: 85-100 % of held-out measurements inside (n ~ 160;
  // ~ 105 at the sanitizers' size).
  const double coverage = static_cast<double>(covered) / p.size();
  RecordProperty("coverage", std::to_string(coverage));
  EXPECT_GE(coverage, 0.85);
}

}  // namespace
}  // namespace rollwear
