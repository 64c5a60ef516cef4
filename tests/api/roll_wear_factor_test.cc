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
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

class RollWearFactorTest : public RouterTest {};

TEST_F(RollWearFactorTest, EachRollShowsItsOwnFactorWithAnInterval) {
  SimulatorOptions so;
  so.seed = 41;
  so.num_campaigns = 160;
  so.roll_wear_factor_sd = 0.2;
  StatusOr<Simulation> sim = Simulate(so);
  ASSERT_TRUE(sim.ok());
  ASSERT_TRUE(store_->ImportDataset(sim->data).ok());
  StatusOr<Dataset> data = store_->ExportDataset();
  ASSERT_TRUE(data.ok());
  StatusOr<DiagnosisReport> report = Diagnose(*data, DiagnosisOptions{});
  ASSERT_TRUE(report.ok());
  const auto roll_finding =
      std::find_if(report->findings.begin(), report->findings.end(),
                   [](const Finding& f) { return f.form == "roll_effect"; });
  ASSERT_NE(roll_finding, report->findings.end());
  auto run = engine::CalibrationRuns(&*store_).Propose(
      "diagnosis 1", "wang", 1, report->adopted_model, *data, 1);
  ASSERT_TRUE(run.ok());
  ASSERT_TRUE(run->promoted) << run->message;

  // The term's rolls, and the common scale: the median of truth / value.
  const ModelTerm& term = roll_finding->term;
  std::vector<double> ratio;
  std::map<std::string, json> served;
  for (const std::string& id : term.levels) {
    HttpResponse r = Get("/v1/rolls/" + id);
    ASSERT_EQ(r.status, 200) << r.body;
    const json life = Parse(r);
    ASSERT_TRUE(life.contains("wear_factor")) << life.dump();
    const auto truth = sim->truth.roll_wear_factor.find(id);
    if (truth == sim->truth.roll_wear_factor.end()) continue;
    served[id] = life["wear_factor"];
    ratio.push_back(truth->second / life["wear_factor"]["value"].get<double>());
  }
  std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2,
                   ratio.end());
  const double scale = ratio[ratio.size() / 2];
  int measured = 0, covered = 0;
  for (const auto& [id, f] : served) {
    const double value = f["value"].get<double>();
    const double lo = f["interval"][0].get<double>();
    const double hi = f["interval"][1].get<double>();
    EXPECT_LT(lo, value);
    EXPECT_GT(hi, value);
    if (f["readings"].get<int>() == 0) continue;
    ++measured;
    const double truth = sim->truth.roll_wear_factor.at(id) / scale;
    covered += truth >= lo && truth <= hi ? 1 : 0;
  }
  ASSERT_GE(measured, 20);
  // 95 % intervals that leave K's own uncertainty out: most, not all.
  EXPECT_GE(static_cast<double>(covered) / measured, 0.8)
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

}  // namespace
}  // namespace rollwear::api::testing
