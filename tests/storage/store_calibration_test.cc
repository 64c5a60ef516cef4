// Calibration runs on stored data: a run on ~60 simulated campaigns
// promotes its model (atomically, recorded with metrics), the open
// campaign is re-predicted under it, and a run that cannot calibrate is
// recorded as failed without touching the active model; nobody reads a
// promotion before its model is installed.
#include <atomic>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::ExpectWearMatchesBatch;
using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenCampaignWithCoils;
using testing::OpenStore;
using testing::SimulatedMill;
using testing::TempDir;

TEST(StoreCalibrationTest, RunOnSimulatedDataPromotesAndRepredicts) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const Dataset data = SimulatedMill(11, 60, 60);
  ASSERT_TRUE(store->ImportDataset(data).ok());
  EXPECT_GT(store->Counters().measurements_since_last_calibration, 0);
  // An open campaign with coils, re-predicted after the promotion.
  OpenCampaignWithCoils(store.get(), "OK", 25);
  ASSERT_FALSE(HasFatalFailure());
  const double prior_wear =
      Mounted(*store).Wear().positions[0].predicted_wear_um;
  const int64_t version_before = store->ActiveModel()->version;
  EXPECT_EQ(version_before, 0);

  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  StatusOr<CalibrationRecord> queued = store->GetCalibration(*id);
  ASSERT_TRUE(queued.ok());
  EXPECT_EQ(queued->status, CalibrationStatus::kQueued);
  EXPECT_EQ(queued->trigger, "api");
  EXPECT_EQ(queued->model, "wang");
  EXPECT_GT(queued->queued_at, 0);

  Status run = engine::CalibrationRuns(&*store).Run(*id);
  ASSERT_TRUE(run.ok()) << run.ToString();
  StatusOr<CalibrationRecord> rec = store->GetCalibration(*id);
  ASSERT_TRUE(rec.ok());
  EXPECT_EQ(rec->status, CalibrationStatus::kDone) << rec->message;
  EXPECT_TRUE(rec->promoted) << rec->message;
  EXPECT_EQ(rec->model_version, 1);
  EXPECT_GT(rec->n_train, 0);
  EXPECT_GT(rec->n_val, 0);
  EXPECT_GT(rec->cost, 0);
  EXPECT_GT(rec->gap_train_um, 0);
  EXPECT_GT(rec->gap_val_um, 0);
  EXPECT_LE(rec->gap_val_um, rec->active_gap_val_um);
  EXPECT_GE(rec->started_at, rec->queued_at);
  EXPECT_GE(rec->finished_at, rec->started_at);
  EXPECT_FALSE(rec->message.empty());
  // Option 1 over the simulated levels: kF per position, kR, kS.
  StatusOr<ModelVersion> active = store->ActiveModel();
  ASSERT_TRUE(active.ok());
  EXPECT_EQ(active->version, 1);
  EXPECT_EQ(active->model, "wang");
  EXPECT_EQ(active->option, 1);
  EXPECT_TRUE(active->active);
  EXPECT_EQ(active->gap_val_um, rec->gap_val_um);
  ASSERT_EQ(
      rec->coefficients.size(),
      static_cast<size_t>(active->wear_model.structure.num_coefficients()));
  EXPECT_EQ(rec->coefficients, active->wear_model.NamedCoefficients());
  EXPECT_EQ(store->Counters().measurements_since_last_calibration, 0);
  const std::vector<ModelVersion> models = store->ListModels();
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].version, 1);
  EXPECT_TRUE(models[0].active);
  EXPECT_EQ(models[0].wear_model.k, active->wear_model.k);

  // The open campaign's rolls now carry the new model's prediction.
  const WearSnapshot snap = Mounted(*store).Wear();
  EXPECT_EQ(snap.model_version, 1);
  EXPECT_NE(snap.positions[0].predicted_wear_um, prior_wear);
  EXPECT_EQ(snap.positions[0].coils, 25);
  ExpectWearMatchesBatch(*store);
  // A calibrated model has an interval.
  EXPECT_LT(snap.positions[0].interval_lo_um, snap.positions[0].interval_hi_um);

  // Not queued any more.
  EXPECT_EQ(engine::CalibrationRuns(&*store).Run(*id).code(),
            StatusCode::kFailedPrecondition);

  // Restart: the promoted model and the re-predicted state come back.
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->ActiveModel()->version, 1);
  const WearSnapshot again = Mounted(*store).Wear();
  ASSERT_EQ(again.positions.size(), snap.positions.size());
  for (size_t i = 0; i < again.positions.size(); ++i) {
    EXPECT_EQ(again.positions[i].predicted_wear_um,
              snap.positions[i].predicted_wear_um);
    EXPECT_EQ(again.positions[i].interval_hi_um,
              snap.positions[i].interval_hi_um);
  }
  EXPECT_EQ(store->Counters().measurements_since_last_calibration, 0);
  ASSERT_EQ(store->ListCalibrations(10).size(), 1u);
  EXPECT_EQ(store->ListCalibrations(10)[0].id, *id);

  // A second run with another law is compared with the active (Wang) model
  // on the same validation campaigns; recorded either way.
  StatusOr<int64_t> id2 =
      store->EnqueueCalibration("nightly", WearLaw::kNikitenko, 3);
  ASSERT_TRUE(id2.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id2).ok());
  StatusOr<CalibrationRecord> rec2 = store->GetCalibration(*id2);
  ASSERT_TRUE(rec2.ok());
  EXPECT_EQ(rec2->status, CalibrationStatus::kDone) << rec2->message;
  EXPECT_EQ(rec2->trigger, "nightly");
  EXPECT_EQ(rec2->option, 3);
  EXPECT_GT(rec2->active_gap_val_um, 0);
  EXPECT_EQ(rec2->promoted, rec2->gap_val_um <= rec2->active_gap_val_um);
  EXPECT_EQ(store->ActiveModel()->version, rec2->promoted ? 2 : 1);
  EXPECT_EQ(store->ListCalibrations(10).size(), 2u);
  EXPECT_EQ(store->ListCalibrations(1).size(), 1u);
  ExpectWearMatchesBatch(*store);
}

// A promotion is published as one step: whoever reads the run as done and
// promoted to version v, or v listed as active, then reads v as the active
// model (and the open campaign's wear under it). The CI's TSan run of the
// daemon once saw "done, model_version 1" and then GET /v1/models/active
// answer version 0: the run's record was committed, and readable, while the
// open campaign was still being re-predicted for the new model. A reader
// polls all through the run; the open campaign is long so that the
// re-prediction takes a while.
TEST(StoreCalibrationTest, ReadersNeverSeeAPromotionBeforeItsModel) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ImportDataset(SimulatedMill(11, 60, 60)).ok());
  OpenCampaignWithCoils(store.get(), "OK", 300);
  ASSERT_FALSE(HasFatalFailure());
  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok()) << id.status().ToString();

  std::atomic<bool> finished{false};
  int polls = 0, seen_done = 0, mismatches = 0;
  std::thread reader([&] {
    while (!finished.load()) {
      ++polls;
      StatusOr<CalibrationRecord> rec = store->GetCalibration(*id);
      if (rec.ok() && rec->status == CalibrationStatus::kDone &&
          rec->promoted) {
        ++seen_done;
        if (store->ActiveModel()->version != rec->model_version) ++mismatches;
        if (Mounted(*store).Wear().model_version != rec->model_version)
          ++mismatches;
      }
      for (const ModelVersion& m : store->ListModels()) {
        if (m.active && store->ActiveModel()->version < m.version) {
          ++mismatches;
        }
      }
    }
  });
  const Status run = engine::CalibrationRuns(&*store).Run(*id);
  finished.store(true);
  reader.join();
  ASSERT_TRUE(run.ok()) << run.ToString();
  StatusOr<CalibrationRecord> rec = store->GetCalibration(*id);
  ASSERT_TRUE(rec.ok());
  ASSERT_TRUE(rec->promoted) << rec->message;
  EXPECT_EQ(mismatches, 0) << "of " << polls << " polls";
  EXPECT_GT(polls, 1);
  EXPECT_EQ(store->ActiveModel()->version, rec->model_version);
  ExpectWearMatchesBatch(*store);
}

TEST(StoreCalibrationTest, FailingRunIsRecordedAndLeavesTheModelAlone) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i + 1, i)).ok());
  }
  const WearSnapshot before = Mounted(*store).Wear();
  StatusOr<ModelVersion> active_before = store->ActiveModel();
  ASSERT_TRUE(active_before.ok());

  // No measurement at all: nothing to calibrate on.
  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  StatusOr<CalibrationRecord> rec = store->GetCalibration(*id);
  ASSERT_TRUE(rec.ok());
  EXPECT_EQ(rec->status, CalibrationStatus::kFailed);
  EXPECT_FALSE(rec->promoted);
  EXPECT_EQ(rec->model_version, 0);
  EXPECT_FALSE(rec->message.empty());
  EXPECT_GT(rec->finished_at, 0);

  StatusOr<ModelVersion> active = store->ActiveModel();
  ASSERT_TRUE(active.ok());
  EXPECT_EQ(active->version, 0);
  EXPECT_EQ(active->wear_model.k, active_before->wear_model.k);
  EXPECT_TRUE(store->ListModels().empty());
  const WearSnapshot after = Mounted(*store).Wear();
  ASSERT_EQ(after.positions.size(), before.positions.size());
  for (size_t i = 0; i < after.positions.size(); ++i) {
    EXPECT_EQ(after.positions[i].predicted_wear_um,
              before.positions[i].predicted_wear_um);
  }

  // A measurement arrives: the nightly counter sees it.
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", 5000, "2")).ok());
  ASSERT_TRUE(
      store->AddMeasurement(MakeMeasurement("C1", 6, Position::kTop, "R6T", 30))
          .ok());
  EXPECT_EQ(store->Counters().measurements_since_last_calibration, 1);
}

TEST(StoreCalibrationTest, InterruptedRunIsMarkedFailedOnRestart) {
  TempDir dir;
  int64_t id = 0;
  {
    auto store = OpenStore(dir.File("mill.db"));
    ASSERT_NE(store, nullptr);
    StatusOr<int64_t> queued =
        store->EnqueueCalibration("cli", WearLaw::kCao, 2);
    ASSERT_TRUE(queued.ok());
    id = *queued;
  }
  {
    // Simulate a crash in the middle of the run.
    StatusOr<std::unique_ptr<Db>> db = Db::Open(dir.File("mill.db"));
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)->Exec("UPDATE calibrations SET status = 'running'").ok());
  }
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  StatusOr<CalibrationRecord> rec = store->GetCalibration(id);
  ASSERT_TRUE(rec.ok());
  EXPECT_EQ(rec->status, CalibrationStatus::kFailed);
  EXPECT_NE(rec->message.find("interrupted"), std::string::npos);
  EXPECT_EQ(rec->model, "cao");
  EXPECT_EQ(rec->option, 2);
}

}  // namespace
}  // namespace rollwear::storage
