// MillStore::RecentWear, the history behind the dashboard: the parity
// points of measured campaigns compare the measurement with what the
// grinder is expected to read under the active model, the same number the
// model's validation uses (core/model/model_eval.h), measurement terms
// included.
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/fit/term_refit.h"
#include "core/model/model_eval.h"
#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "tests/core/served_terms_util.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::OpenStore;
using testing::SimulatedMill;
using testing::TempDir;

// (campaign id, "stand/position") -> expected reading, by the offline
// evaluation of `model` over `data`.
std::map<std::pair<std::string, std::string>, MeasuredPrediction> Offline(
    const WearModel& model, const Dataset& data) {
  const DatasetIndex index(data);
  std::vector<int> all;
  for (int c = 0; c < static_cast<int>(data.campaigns.size()); ++c) {
    all.push_back(c);
  }
  std::map<std::pair<std::string, std::string>, MeasuredPrediction> out;
  for (const MeasuredPrediction& p : PredictMeasured(model, data, index, all)) {
    const Measurement& m = data.measurements[p.measurement];
    out[{data.campaigns[p.campaign].id,
         std::to_string(m.stand) + "/" + PositionName(m.position)}] = p;
  }
  return out;
}

// Every measured roll of the last 20 ended campaigns: expected reading and
// final wear as the offline evaluation has them; returns how many rolls
// had an expected reading that differs from the wear by more than 1 µm.
int ExpectHistoryMatchesOffline(const MillStore& store) {
  StatusOr<ModelVersion> active = store.ActiveModel();
  StatusOr<Dataset> data = store.ExportDataset();
  StatusOr<std::vector<CampaignWearHistory>> history = store.RecentWear(20);
  EXPECT_TRUE(active.ok() && data.ok() && history.ok());
  if (!active.ok() || !data.ok() || !history.ok()) return -1;
  const auto offline = Offline(active->wear_model, *data);
  int shifted = 0, measured = 0;
  for (const CampaignWearHistory& c : *history) {
    for (const RollWearHistory& h : c.rolls) {
      if (!h.measured_um) continue;
      ++measured;
      const auto it =
          offline.find({c.campaign_id, std::to_string(h.stand) + "/" +
                                           PositionName(h.position)});
      EXPECT_NE(it, offline.end()) << c.campaign_id;
      if (it == offline.end()) continue;
      const MeasuredPrediction& p = it->second;
      EXPECT_NEAR(h.final_predicted_um, p.wear_um, 1e-9 * p.wear_um);
      EXPECT_NEAR(h.expected_reading_um, p.expected_um,
                  1e-9 * std::abs(p.wear_um));
      EXPECT_EQ(*h.measured_um, p.measured_um);
      if (std::abs(h.expected_reading_um - h.final_predicted_um) > 1) {
        ++shifted;
      }
    }
  }
  EXPECT_EQ(measured, 20 * 4);
  return shifted;
}

TEST(StoreHistoryTest, ParityUsesTheExpectedReadingWithMeasurementTerms) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const Dataset mill = SimulatedMill(21, 60, 40, {"warm_measurement"});
  ASSERT_TRUE(store->ImportDataset(mill).ok());
  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  ASSERT_TRUE(store->GetCalibration(*id)->promoted);

  // Classical model: the expected reading is the wear.
  EXPECT_EQ(ExpectHistoryMatchesOffline(*store), 0);

  // The diagnosis's adopted model (option 1 plus a measurement term on
  // cooling_h), promoted as the daemon's diagnosis job does.
  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  StatusOr<DiagnosisReport> report = Diagnose(*data, DiagnosisOptions{});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  bool has_measurement_term = false;
  for (const ModelTerm& t : report->adopted_model.terms) {
    has_measurement_term |= t.IsMeasurementTerm() && t.covariate == "cooling_h";
  }
  ASSERT_TRUE(has_measurement_term) << report->verdict;
  StatusOr<CalibrationRecord> run = engine::CalibrationRuns(&*store).Propose(
      "test", "wang", 1, report->adopted_model, *data, 1);
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  ASSERT_TRUE(run->promoted) << run->message;

  // Now the readings of rolls measured warm sit below their wear, exactly
  // as the validation that promoted the model computed them.
  EXPECT_GT(ExpectHistoryMatchesOffline(*store), 0);
}

// The issue-15 vocabulary served by the daemon: a scoped log-linear term, a
// cell term, a per-level offset on the grinder column of measurements.csv
// (its levels matched by label) and a scoped measured_at drift. The
// replay's expected readings equal the offline evaluation (which equals the
// fit's batch prediction: tests/core/served_terms_test.cc) to 1e-9.
TEST(StoreHistoryTest, ExpectedReadingServesScopedCellAndTextColumnTerms) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const Dataset mill = SimulatedMill(23, 60, 40, {"grinder:0"});
  ASSERT_EQ(mill.measurement_extra.factor_names.size(), 1u);
  ASSERT_TRUE(store->ImportDataset(mill).ok());
  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());

  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  std::vector<int> all;
  for (int c = 0; c < static_cast<int>(data->campaigns.size()); ++c)
    all.push_back(c);
  StatusOr<WearModel> model = RefitWithTerms(
      *data, WearLaw::kWang, served_terms::VocabularyTerms(*data, 0), all);
  ASSERT_TRUE(model.ok()) << model.status().ToString();
  StatusOr<CalibrationRecord> run = engine::CalibrationRuns(&*store).Propose(
      "test", "wang", 1, *model, *data, 1);
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  ASSERT_GT(run->model_version, 0) << run->message;
  if (!run->promoted) {
    ASSERT_TRUE(store->ActivateModel(run->model_version, "test", false).ok());
  }
  StatusOr<ModelVersion> active = store->ActiveModel();
  ASSERT_TRUE(active.ok());
  ASSERT_EQ(active->wear_model.terms.size(), 4u);
  EXPECT_EQ(active->wear_model.terms[1].scope.roll_type, data->roll_types[0]);
  // The grinder's non-reference level reads its offset: many rolls shift.
  EXPECT_GT(ExpectHistoryMatchesOffline(*store), 20);
}

}  // namespace
}  // namespace rollwear::storage
