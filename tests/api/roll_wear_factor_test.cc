// Each roll's own wear factor in the daemon: a simulated mill whose rolls
// wear by lifelong factors is diagnosed (core), the adopted model with its
// per-roll family is proposed and promoted through the engine on the real
// store, and GET /v1/rolls/{roll_id} then gives every measured roll its
// multiplier with an interval that holds the simulator's factor (up to the
// common scale K takes), a roll the model never saw its type's value, and
// the roll page says the same.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"
#include "engine/calibration_runs.h"
#include "engine/wear_prediction.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

class RollWearFactorTest : public RouterTest {
 protected:
  // Imports a simulated mill whose rolls wear by lifelong factors,
  // diagnoses it and promotes the adopted model with its roll-effect term
  // (sim_, term_).
  void PromoteRollModel() {
    SimulatorOptions so;
    so.seed = 41;
    so.num_campaigns = 160;
    so.roll_wear_factor_sd = 0.2;
    StatusOr<Simulation> sim = Simulate(so);
    ASSERT_TRUE(sim.ok());
    sim_ = std::move(sim).value();
    ASSERT_TRUE(store_->ImportDataset(sim_.data).ok());
    StatusOr<Dataset> data = store_->ExportDataset();
    ASSERT_TRUE(data.ok());
    StatusOr<DiagnosisReport> report = Diagnose(*data, DiagnosisOptions{});
    ASSERT_TRUE(report.ok());
    const auto roll_finding =
        std::find_if(report->findings.begin(), report->findings.end(),
                     [](const Finding& f) { return f.form == "roll_effect"; });
    ASSERT_NE(roll_finding, report->findings.end());
    term_ = roll_finding->term;
    auto run = engine::CalibrationRuns(&*store_).Propose(
        "diagnosis 1", "wang", 1, report->adopted_model, *data, 1);
    ASSERT_TRUE(run.ok());
    ASSERT_TRUE(run->promoted) << run->message;
  }

  // Rolls 60 coils in the open campaign `id` (the test rolls R-F6-top ...)
  // on `day`; ends it with the roll change `next` unless that is empty.
  // Returns the roll R-F6-top's life.
  json RunTestCampaign(const std::string& id, const std::string& day,
                       const std::string& next) {
    for (int i = 0; i < 60; ++i) {
      const std::string at = day + "T07:" + (i < 10 ? "0" : "") +
                             std::to_string(i) + ":00Z";
      EXPECT_EQ(Post("/v1/coils", CoilBody(id + "-" + std::to_string(i), id,
                                           i + 1, at))
                    .status,
                201);
    }
    if (!next.empty()) {
      EXPECT_EQ(
          Post("/v1/roll-changes", RollChangeBody(next, day + "T20:00:00Z"))
              .status,
          201);
    }
    return Parse(Get("/v1/rolls/R-F6-top"));
  }

  // The grinder's reading of R-F6-top after campaign `id`.
  int Measure(const std::string& id, const std::string& day, double um) {
    json m = MeasurementBody(id, "F6", "top", "R-F6-top", um);
    m["measured_at"] = day + "T21:00:00Z";
    return Post("/v1/measurements", m).status;
  }

  // The live predicted wear at F6/top (GET /v1/wear/F6/top).
  double LiveWear() {
    const json wear = Parse(Get("/v1/wear/F6/top"));
    return wear["predicted_wear_um"].get<double>();
  }

  // The mount of campaign `id` in a roll's life (null when none).
  static json MountOf(const json& life, const std::string& id) {
    for (const json& m : life["mounts"]) {
      if (m["campaign_id"] == id) return m;
    }
    return nullptr;
  }

  Simulation sim_;
  ModelTerm term_;
};

TEST_F(RollWearFactorTest, EachRollShowsItsOwnFactorWithAnInterval) {
  ASSERT_NO_FATAL_FAILURE(PromoteRollModel());
  // The term's rolls, and the scale K takes for each roll type (kR
  // absorbs the mean factor of the type's rolls): the median of truth /
  // value over the type's rolls.
  const ModelTerm& term = term_;
  std::map<std::string, std::vector<double>> ratios;  // by roll type
  std::map<std::string, std::pair<std::string, json>> served;  // type, factor
  for (const std::string& id : term.levels) {
    HttpResponse r = Get("/v1/rolls/" + id);
    ASSERT_EQ(r.status, 200) << r.body;
    const json life = Parse(r);
    ASSERT_TRUE(life.contains("wear_factor")) << life.dump();
    const auto truth = sim_.truth.roll_wear_factor.find(id);
    if (truth == sim_.truth.roll_wear_factor.end()) continue;
    const std::string type = life["roll_type"].get<std::string>();
    served[id] = {type, life["wear_factor"]};
    ratios[type].push_back(truth->second /
                           life["wear_factor"]["value"].get<double>());
  }
  std::map<std::string, double> scale;
  for (auto& [type, r] : ratios) {
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    scale[type] = r[r.size() / 2];
  }
  int measured = 0, covered = 0;
  for (const auto& [id, typed] : served) {
    const json& f = typed.second;
    const double value = f["value"].get<double>();
    const double lo = f["interval"][0].get<double>();
    const double hi = f["interval"][1].get<double>();
    EXPECT_LT(lo, value);
    EXPECT_GT(hi, value);
    if (f["readings"].get<int>() == 0) continue;
    ++measured;
    const double truth =
        sim_.truth.roll_wear_factor.at(id) / scale.at(typed.first);
    covered += truth >= lo && truth <= hi ? 1 : 0;
  }
  ASSERT_GE(measured, 20);
  // 95 % intervals that leave K's own uncertainty out (107 of 116 here).
  EXPECT_GE(static_cast<double>(covered) / measured, 0.85)
      << covered << " of " << measured;
  EXPECT_LE(static_cast<double>(covered) / measured, 0.99)
      << covered << " of " << measured;

  // A roll the model never saw: its type's value, no readings.
  ASSERT_EQ(
      Post("/v1/roll-changes", RollChangeBody("NEW1", "2027-01-01T06:00:00Z"))
          .status,
      201);
  const json fresh = Parse(Get("/v1/rolls/R-F6-top"));
  ASSERT_TRUE(fresh.contains("wear_factor")) << fresh.dump();
  EXPECT_EQ(fresh["wear_factor"]["value"], 1.0);
  EXPECT_EQ(fresh["wear_factor"]["readings"], 0);
  EXPECT_LT(fresh["wear_factor"]["interval"][0].get<double>(), 1.0);

  // The page says it in words.
  const std::string page = Get("/rolls/" + term.levels.front()).body;
  EXPECT_NE(page.find("id=\"wear-factor\""), std::string::npos);
  EXPECT_NE(page.find("Own wear factor"), std::string::npos);
}

// The daemon keeps each roll's factor current between calibrations: a roll
// the model never saw starts at its type's value; each measurement of its
// campaigns moves the factor toward what the grinder read and narrows its
// interval; the roll's predictions (replayed, and live in the open
// campaign it runs in when the reading comes) are made with it; a restart
// finds the same factor and the same live wear.
TEST_F(RollWearFactorTest, ARollsFactorFollowsItsMeasurementsAsTheyArrive) {
  ASSERT_NO_FATAL_FAILURE(PromoteRollModel());
  ASSERT_EQ(
      Post("/v1/roll-changes", RollChangeBody("NEW1", "2027-01-01T06:00:00Z"))
          .status,
      201);
  json life = RunTestCampaign("NEW1", "2027-01-01", "NEW2");
  ASSERT_TRUE(life.contains("wear_factor")) << life.dump();
  EXPECT_EQ(life["wear_factor"]["readings"], 0);
  EXPECT_EQ(life["wear_factor"]["value"], 1.0);
  const double prior_width = life["wear_factor"]["interval"][1].get<double>() -
                             life["wear_factor"]["interval"][0].get<double>();
  const double base = MountOf(life, "NEW1")["predicted_wear_um"].get<double>();
  ASSERT_GT(base, 20);
  // NEW2 rolls the same coils before NEW1's reading comes: the same wear.
  RunTestCampaign("NEW2", "2027-01-02", "");
  EXPECT_NEAR(LiveWear(), base, 1e-9 * base);

  // The grinder reads 1.5 x what the roll's type would wear.
  ASSERT_EQ(Measure("NEW1", "2027-01-01", 1.5 * base), 201);
  life = Parse(Get("/v1/rolls/R-F6-top"));
  const json f1 = life["wear_factor"];
  EXPECT_EQ(f1["readings"], 1);
  const double v1 = f1["value"].get<double>();
  EXPECT_GT(v1, 1.03);
  EXPECT_LT(v1, 1.5);
  const double width1 =
      f1["interval"][1].get<double>() - f1["interval"][0].get<double>();
  EXPECT_LT(width1, prior_width);
  // NEW1 replayed with the roll's factor, and NEW2's live state too.
  EXPECT_NEAR(MountOf(life, "NEW1")["predicted_wear_um"].get<double>() / base,
              v1, 1e-6 * v1);
  EXPECT_NEAR(LiveWear(), v1 * base, 1e-6 * v1 * base);

  // A second reading at 1.5 x: closer to 1.5, narrower.
  ASSERT_EQ(Post("/v1/roll-changes",
                 RollChangeBody("NEW3", "2027-01-02T20:00:00Z"))
                .status,
            201);
  ASSERT_EQ(Measure("NEW2", "2027-01-02", 1.5 * base), 201);
  const json f2 = Parse(Get("/v1/rolls/R-F6-top"))["wear_factor"];
  EXPECT_EQ(f2["readings"], 2);
  const double v2 = f2["value"].get<double>();
  EXPECT_GT(v2, v1);
  EXPECT_LT(v2, 1.5);
  EXPECT_LT(f2["interval"][1].get<double>() - f2["interval"][0].get<double>(),
            width1);
  RunTestCampaign("NEW3", "2027-01-03", "");
  const double live = LiveWear();
  EXPECT_NEAR(live, v2 * base, 1e-6 * v2 * base);

  // The version as stored keeps its calibration's factors: this roll had
  // no reading then.
  const json stored = Parse(Get("/v1/models/active"))["terms"];
  const auto term = std::find_if(stored.begin(), stored.end(), [](const json& t) {
    return t["form"] == "roll_effect";
  });
  ASSERT_NE(term, stored.end()) << stored.dump();
  const json& levels = (*term)["levels"];
  const auto at = std::find(levels.begin(), levels.end(), "R-F6-top");
  ASSERT_NE(at, levels.end()) << term->dump();
  const size_t l = static_cast<size_t>(at - levels.begin());
  EXPECT_EQ((*term)["params"][l], 0.0);
  EXPECT_EQ((*term)["level_readings"][l], 0);

  // A restart re-estimates the same factor from the stored readings and
  // replays the open campaign to the same wear.
  router_.reset();
  diagnoses_.reset();
  runs_.reset();
  store_.reset();
  StatusOr<std::unique_ptr<storage::MillStore>> reopened =
      engine::OpenStore(dir_ + "/api.db");
  ASSERT_TRUE(reopened.ok()) << reopened.status().ToString();
  store_ = std::move(reopened).value();
  MakeRouter(ApiOptions());
  const json f3 = Parse(Get("/v1/rolls/R-F6-top"))["wear_factor"];
  EXPECT_EQ(f3["readings"], 2);
  EXPECT_NEAR(f3["value"].get<double>(), v2, 1e-9 * v2);
  EXPECT_NEAR(LiveWear(), live, 1e-9 * live);
}

}  // namespace
}  // namespace rollwear::api::testing
