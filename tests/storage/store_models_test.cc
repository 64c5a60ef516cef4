// Model versions beyond the classical calibration, on a real SQLite file:
//  - a diagnosis's adopted model (option 1 + terms) proposed to the store is
//    promoted only when no worse on the validation campaigns, the open
//    campaign is re-predicted with its terms coil by coil, and a nightly
//    run afterwards refits the terms instead of dropping them;
//  - the recurrent network trained by a run (model "ann") is served with
//    an interval and survives a restart bit for bit.
#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/model/predictor.h"
#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "tests/core/test_size.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenCampaignWithCoils;
using testing::OpenStore;
using testing::RelDiff;
using testing::SimulatedMill;
using testing::TempDir;

// Live wear of the open campaign equals the active model run coil by coil
// over the stored passes (terms and network included).
void ExpectLiveWearIsCoilByCoil(const MillStore& store) {
  const WearSnapshot snap = Mounted(store).Wear();
  ASSERT_FALSE(snap.positions.empty());
  StatusOr<ModelVersion> active = store.ActiveModel();
  ASSERT_TRUE(active.ok());
  StatusOr<Dataset> data = store.ExportDataset();
  ASSERT_TRUE(data.ok());
  const DatasetIndex index(*data);
  int campaign = -1;
  for (size_t c = 0; c < data->campaigns.size(); ++c) {
    if (data->campaigns[c].id == snap.positions.front().campaign_id)
      campaign = c;
  }
  ASSERT_GE(campaign, 0);
  for (const PositionWear& w : snap.positions) {
    const int mi =
        index.MountOf(campaign, RollPositionSlot(w.stand, w.position));
    ASSERT_GE(mi, 0);
    const Mount& m = data->mounts[mi];
    RollWearState st =
        MountRoll(active->wear_model, RollPositionName(m.stand, m.position),
                  data->roll_types[m.roll_type], m.diameter_mm, m.hardness_hb,
                  data->campaigns[campaign].started_at);
    for (int pi : index.PassesOf(campaign, m.stand)) {
      AddPass(active->wear_model, PassInputOf(*data, data->passes[pi]), &st);
    }
    EXPECT_LE(RelDiff(w.predicted_wear_um, st.wear_um), 1e-9)
        << RollPositionName(w.stand, w.position);
    EXPECT_EQ(w.coils, st.coils);
    EXPECT_LT(w.interval_lo_um, w.predicted_wear_um);
    EXPECT_GT(w.interval_hi_um, w.predicted_wear_um);
  }
}

TEST(StoreModelsTest, AdoptedTermsArePromotedServedAndKeptByTheNightlyRun) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(
      store->ImportDataset(SimulatedMill(12, 160, 80, {"campaign_growth"}))
          .ok());
  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  const CalibrationRecord classical = *store->GetCalibration(*id);
  ASSERT_TRUE(classical.promoted) << classical.message;
  OpenCampaignWithCoils(store.get(), "OC", 40);

  // The diagnosis of the stored data, as the daemon's job runs it.
  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  StatusOr<DiagnosisReport> report = Diagnose(*data, DiagnosisOptions{});
  ASSERT_TRUE(report.ok());
  ASSERT_EQ(report->verdict, "missing_physics_found");
  ASSERT_FALSE(report->adopted_model.terms.empty());

  // A spoiled copy (the growth term's amplitude reversed) is worse than the
  // classical model on validation: recorded, not promoted.
  WearModel spoiled = report->adopted_model;
  spoiled.terms[0].params[0] =
      -0.8 * std::abs(spoiled.terms[0].params[0]) - 0.2;
  StatusOr<CalibrationRecord> bad = engine::CalibrationRuns(&*store).Propose(
      "test", "wang", 1, spoiled, *data, 1);
  ASSERT_TRUE(bad.ok()) << bad.status().ToString();
  EXPECT_EQ(bad->status, CalibrationStatus::kDone);
  EXPECT_FALSE(bad->promoted) << bad->message;
  EXPECT_GT(bad->gap_val_um, bad->active_gap_val_um);
  EXPECT_EQ(store->ActiveModel()->version, classical.model_version);

  // The adopted model itself: promoted, its validation gap below the
  // classical model's on the same campaigns.
  StatusOr<CalibrationRecord> run = engine::CalibrationRuns(&*store).Propose(
      "diagnosis 1", "wang", 1, report->adopted_model, *data, 1);
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  EXPECT_EQ(run->status, CalibrationStatus::kDone);
  EXPECT_EQ(run->trigger, "diagnosis 1");
  EXPECT_TRUE(run->promoted) << run->message;
  EXPECT_NEAR(run->active_gap_val_um, classical.gap_val_um,
              1e-9 * classical.gap_val_um);
  EXPECT_LT(run->gap_val_um, 0.95 * classical.gap_val_um);
  EXPECT_NEAR(run->gap_val_um, report->final_gap_val_um,
              1e-6 * report->final_gap_val_um);
  StatusOr<ModelVersion> active = store->ActiveModel();
  ASSERT_TRUE(active.ok());
  EXPECT_EQ(active->version, run->model_version);
  ASSERT_EQ(active->wear_model.terms.size(),
            report->adopted_model.terms.size());
  EXPECT_EQ(active->wear_model.terms[0].params,
            report->adopted_model.terms[0].params);
  ExpectLiveWearIsCoilByCoil(*store);
  // The run is recorded (listed with the calibrations).
  EXPECT_EQ(store->GetCalibration(run->id)->status, CalibrationStatus::kDone);
  EXPECT_EQ(store->ListCalibrations(1).front().id, run->id);

  // More coils are added under the adopted model, incrementally.
  for (int i = 40; i < 60; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("OC" + std::to_string(i), "OPEN", i + 1, i))
            .ok());
  }
  ExpectLiveWearIsCoilByCoil(*store);

  // The nightly run (Wang, option 1) refits the adopted terms.
  StatusOr<int64_t> nightly =
      store->EnqueueCalibration("nightly", WearLaw::kWang, 1);
  ASSERT_TRUE(nightly.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*nightly).ok());
  const CalibrationRecord refit = *store->GetCalibration(*nightly);
  EXPECT_EQ(refit.status, CalibrationStatus::kDone) << refit.message;
  EXPECT_NE(refit.message.find("adopted term(s) refitted"), std::string::npos)
      << refit.message;
  EXPECT_LT(refit.gap_val_um, 0.95 * classical.gap_val_um);
  // Refitted on the same training campaigns the adopted fit used: the same
  // gain, within 3 % (a refit that dropped the terms would be >= 5 % worse).
  EXPECT_NEAR(refit.gap_val_um, run->gap_val_um, 0.03 * run->gap_val_um);
  EXPECT_EQ(refit.promoted, refit.gap_val_um <= refit.active_gap_val_um);
  if (refit.promoted) {
    EXPECT_EQ(store->ActiveModel()->wear_model.terms.size(),
              report->adopted_model.terms.size());
  }

  // Restart: the model with terms is decoded and serves the same numbers.
  const WearSnapshot before = Mounted(*store).Wear();
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_FALSE(store->ActiveModel()->wear_model.terms.empty());
  const WearSnapshot after = Mounted(*store).Wear();
  ASSERT_EQ(after.positions.size(), before.positions.size());
  for (size_t i = 0; i < after.positions.size(); ++i) {
    EXPECT_EQ(after.positions[i].predicted_wear_um,
              before.positions[i].predicted_wear_um);
    EXPECT_EQ(after.positions[i].interval_hi_um,
              before.positions[i].interval_hi_um);
  }
}

// Under the sanitizers (test_size.h) the network trains on 90 campaigns of
// 50 coils instead of 160 of 80: the slowest test there (82 s under ASan,
// 91 s under TSan, session 16) at about a quarter of the time (Release: 6.0
// s -> 1.5 s); it asserts the same at both sizes, and the smaller mill
// promoted the network for seeds 7, 8, 9 and 12 alike.
TEST(StoreModelsTest, AnnRunIsRecordedAndTheNetworkIsServedAcrossRestarts) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store
                  ->ImportDataset(SimulatedMill(12, test_size::FullOr(160, 90),
                                                test_size::FullOr(80, 50),
                                                {"campaign_growth"}))
                  .ok());
  OpenCampaignWithCoils(store.get(), "OC", 30);
  StatusOr<int64_t> id = store->EnqueueCalibration("api", ModelChoice::Network());
  ASSERT_TRUE(id.ok());
  EXPECT_EQ(store->GetCalibration(*id)->model, "ann");
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  const CalibrationRecord rec = *store->GetCalibration(*id);
  ASSERT_EQ(rec.status, CalibrationStatus::kDone) << rec.message;
  EXPECT_GT(rec.gap_val_um, 0);
  EXPECT_GT(rec.n_val, 0);
  // Against the uncalibrated prior the network is better on validation.
  ASSERT_TRUE(rec.promoted) << rec.message;
  EXPECT_LT(rec.gap_val_um, rec.active_gap_val_um);
  StatusOr<ModelVersion> active = store->ActiveModel();
  ASSERT_TRUE(active.ok());
  EXPECT_EQ(active->model, "ann");
  ASSERT_TRUE(active->wear_model.is_ann());
  ExpectLiveWearIsCoilByCoil(*store);
  for (int i = 30; i < 45; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("OC" + std::to_string(i), "OPEN", i + 1, i))
            .ok());
  }
  ExpectLiveWearIsCoilByCoil(*store);

  const WearSnapshot before = Mounted(*store).Wear();
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->ActiveModel()->model, "ann");
  const WearSnapshot after = Mounted(*store).Wear();
  ASSERT_EQ(after.positions.size(), before.positions.size());
  for (size_t i = 0; i < after.positions.size(); ++i) {
    EXPECT_EQ(after.positions[i].predicted_wear_um,
              before.positions[i].predicted_wear_um);
    EXPECT_EQ(after.positions[i].interval_lo_um,
              before.positions[i].interval_lo_um);
  }
}

}  // namespace
}  // namespace rollwear::storage
