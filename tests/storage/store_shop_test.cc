// Models under control, rolls across campaigns and stored diagnoses, on a
// real SQLite file (schema version 6):
//  - activating an earlier version by hand pins it, re-predicts the open
//    campaign under it, is one row of the audit trail, keeps calibration
//    runs and diagnosis adoptions from replacing it, and survives a
//    restart; activating with pin false unpins; bad requests change nothing;
//  - a roll's life lists each mount with the coils, length and wear it
//    had, the inventory sums them;
//  - a finished diagnosis is read back after a restart.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenCampaignWithCoils;
using testing::OpenStore;
using testing::RelDiff;
using testing::SimulatedMill;
using testing::TempDir;

void ExpectSameWear(const WearSnapshot& a, const WearSnapshot& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (size_t i = 0; i < a.positions.size(); ++i) {
    EXPECT_LE(RelDiff(a.positions[i].predicted_wear_um,
                      b.positions[i].predicted_wear_um),
              1e-12)
        << i;
    EXPECT_EQ(a.positions[i].coils, b.positions[i].coils);
  }
}

// v1 from a nightly calibration, an open campaign, then v2 (the same model
// proposed by "diagnosis 7", equal gap: promoted). *v1_wear: Wear() under v1.
void TwoVersions(MillStore* store, WearSnapshot* v1_wear) {
  ASSERT_TRUE(store->ImportDataset(SimulatedMill(5, 24, 50)).ok());
  StatusOr<int64_t> id =
      store->EnqueueCalibration("nightly", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  ASSERT_TRUE(store->GetCalibration(*id)->promoted);
  OpenCampaignWithCoils(store, "OC", 12);
  ASSERT_FALSE(::testing::Test::HasFatalFailure());
  *v1_wear = Mounted(*store).Wear();
  ASSERT_EQ(v1_wear->model_version, 1);
  WearModel other = store->ActiveModel()->wear_model;
  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  // Same law, k 10 % up: another version, scored on the same campaigns.
  for (double& k : other.k) k *= 1.1;
  StatusOr<CalibrationRecord> run = engine::CalibrationRuns(&*store).Propose(
      "diagnosis 7", "wang", 1, other, *data, 1);
  ASSERT_TRUE(run.ok());
  if (!run->promoted) {
    // The spoiled copy lost: propose the active one itself (equal gap).
    run = engine::CalibrationRuns(&*store).Propose(
        "diagnosis 7", "wang", 1, store->ActiveModel()->wear_model, *data, 1);
    ASSERT_TRUE(run.ok());
  }
  ASSERT_TRUE(run->promoted) << run->message;
  ASSERT_EQ(store->ActiveModel()->version, 2);
}

TEST(StoreShopTest, ActivatedVersionIsPinnedAuditedAndSurvivesRestart) {
  TempDir dir;
  WearSnapshot v1_wear;
  {
    auto store = OpenStore(dir.File("mill.db"));
    ASSERT_NE(store, nullptr);
    TwoVersions(store.get(), &v1_wear);
    const WearSnapshot v2_wear = Mounted(*store).Wear();

    // Refused: nothing changes.
    StatusOr<ModelVersion> r = store->ActivateModel(1, "  ", true);
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(r.status().message().rfind("reason: ", 0), 0u);
    EXPECT_EQ(store->ActivateModel(99, "x", true).status().code(),
              StatusCode::kNotFound);
    EXPECT_EQ(store->ActivateModel(0, "x", true).status().code(),
              StatusCode::kNotFound);
    EXPECT_EQ(store->ActiveModel()->version, 2);
    ExpectSameWear(Mounted(*store).Wear(), v2_wear);
    ASSERT_EQ(store->ModelHistory(0)->size(), 2u);

    r = store->ActivateModel(1, "v2 over-predicts F7", true);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_TRUE(r->pinned);
    EXPECT_EQ(store->ActiveModel()->version, 1);
    EXPECT_TRUE(store->ActiveModel()->pinned);
    // The open campaign is re-predicted under v1: what it was under v1.
    EXPECT_EQ(Mounted(*store).Wear().model_version, 1);
    ExpectSameWear(Mounted(*store).Wear(), v1_wear);

    // A nightly run and a diagnosis adoption record, but do not promote.
    StatusOr<int64_t> id =
        store->EnqueueCalibration("nightly", WearLaw::kWang, 1);
    ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
    const CalibrationRecord nightly = *store->GetCalibration(*id);
    EXPECT_EQ(nightly.status, CalibrationStatus::kDone);
    EXPECT_FALSE(nightly.promoted);
    EXPECT_NE(nightly.message.find("model pinned"), std::string::npos)
        << nightly.message;
    StatusOr<Dataset> data = store->ExportDataset();
    StatusOr<CalibrationRecord> adoption =
        engine::CalibrationRuns(&*store).Propose(
            "diagnosis 8", "wang", 1, store->ActiveModel()->wear_model, *data,
            1);
    ASSERT_TRUE(adoption.ok());
    EXPECT_FALSE(adoption->promoted);
    EXPECT_EQ(store->ActiveModel()->version, 1);
  }
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->ActiveModel()->version, 1);
  EXPECT_TRUE(store->ActiveModel()->pinned);
  ExpectSameWear(Mounted(*store).Wear(), v1_wear);

  StatusOr<std::vector<ModelPromotion>> h = store->ModelHistory(0);
  ASSERT_TRUE(h.ok());
  ASSERT_EQ(h->size(), 3u);
  EXPECT_EQ((*h)[0].version, 1);
  EXPECT_EQ((*h)[0].previous_version, 2);
  EXPECT_EQ((*h)[0].source, "manual");
  EXPECT_EQ((*h)[0].reason, "v2 over-predicts F7");
  EXPECT_TRUE((*h)[0].pinned);
  EXPECT_EQ((*h)[1].version, 2);
  EXPECT_EQ((*h)[1].previous_version, 1);
  EXPECT_EQ((*h)[1].source, "diagnosis");
  EXPECT_EQ((*h)[2].version, 1);
  EXPECT_EQ((*h)[2].previous_version, 0);
  EXPECT_EQ((*h)[2].source, "nightly");
  EXPECT_EQ(store->ModelHistory(1)->size(), 1u);

  StatusOr<ModelVersion> v2 = store->GetModel(2);
  ASSERT_TRUE(v2.ok());
  EXPECT_EQ(v2->source, "diagnosis");
  EXPECT_EQ(v2->trigger, "diagnosis 7");
  EXPECT_GT(v2->calibration_id, 0);
  EXPECT_FALSE(v2->active);
  EXPECT_GT(store->GetModel(1)->n_val, 0);
  EXPECT_GT(store->GetModel(1)->gap_train_um, 0);

  // Unpinned: runs may promote again.
  StatusOr<ModelVersion> r = store->ActivateModel(1, "back to normal", false);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(store->ActiveModel()->pinned);
  StatusOr<int64_t> id =
      store->EnqueueCalibration("nightly", WearLaw::kWang, 1);
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  const CalibrationRecord after = *store->GetCalibration(*id);
  EXPECT_EQ(after.message.find("pinned"), std::string::npos);
  EXPECT_EQ(after.promoted, after.gap_val_um <= after.active_gap_val_um);
  EXPECT_EQ(store->ModelHistory(0)->size(), after.promoted ? 5u : 4u);
}

// A run is compared with the version active when it started; a version
// activated by hand while it ran stays, and the run says why it did not
// promote (the store's own guard: the engine's runs do not hold a lock the
// activation waits on).
TEST(StoreShopTest, VersionActivatedDuringARunIsNotReplacedByIt) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  WearSnapshot v1_wear;
  TwoVersions(store.get(), &v1_wear);
  ASSERT_FALSE(HasFatalFailure());
  const ModelVersion v2 = *store->ActiveModel();

  // The run starts against version 2 ...
  StatusOr<CalibrationRecord> run = store->StartProposal("test", "wang", 1);
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  // ... version 1 is activated by hand, unpinned, while it runs ...
  ASSERT_TRUE(store->ActivateModel(1, "operator's choice", false).ok());
  // ... and the run, which the engine decided to promote, finishes.
  run->status = CalibrationStatus::kDone;
  run->message = "proposed by test";
  ModelVersion candidate;
  candidate.wear_model = v2.wear_model;
  ASSERT_TRUE(
      store->FinishCalibration(&*run, candidate, /*replaced_version=*/2).ok());
  EXPECT_FALSE(run->promoted);
  EXPECT_EQ(run->model_version, 0);
  EXPECT_NE(run->message.find("version 1 became active during the run"),
            std::string::npos)
      << run->message;
  EXPECT_EQ(store->ActiveModel()->version, 1);
  EXPECT_EQ(store->ListModels().size(), 2u);
  const StatusOr<CalibrationRecord> stored = store->GetCalibration(run->id);
  ASSERT_TRUE(stored.ok());
  EXPECT_FALSE(stored->promoted);
  EXPECT_EQ(stored->message, run->message);

  // Against the version now active, the same candidate is promoted.
  StatusOr<CalibrationRecord> next = store->StartProposal("test", "wang", 1);
  ASSERT_TRUE(next.ok());
  next->status = CalibrationStatus::kDone;
  ASSERT_TRUE(
      store->FinishCalibration(&*next, candidate, /*replaced_version=*/1).ok());
  EXPECT_TRUE(next->promoted) << next->message;
  EXPECT_EQ(store->ActiveModel()->version, 3);

  // A finished run cannot be finished again, nor a run that failed promote.
  EXPECT_EQ(store->FinishCalibration(&*next, std::nullopt, 3).code(),
            StatusCode::kFailedPrecondition);
  StatusOr<CalibrationRecord> failed = store->StartProposal("test", "wang", 1);
  ASSERT_TRUE(failed.ok());
  failed->status = CalibrationStatus::kFailed;
  EXPECT_EQ(store->FinishCalibration(&*failed, candidate, 3).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(store->ActiveModel()->version, 3);

  // The version the run was compared with, pinned by hand while it ran,
  // stays too.
  StatusOr<CalibrationRecord> pinned = store->StartProposal("test", "wang", 1);
  ASSERT_TRUE(pinned.ok());
  ASSERT_TRUE(store->ActivateModel(3, "hold it", true).ok());
  pinned->status = CalibrationStatus::kDone;
  ASSERT_TRUE(store->FinishCalibration(&*pinned, candidate, 3).ok());
  EXPECT_FALSE(pinned->promoted);
  EXPECT_NE(pinned->message.find("model pinned during the run (version 3"),
            std::string::npos)
      << pinned->message;
  EXPECT_EQ(store->ActiveModel()->version, 3);
}

// A version-4 file's model versions each get one audit row on upgrade.
TEST(StoreShopTest, UpgradeGivesStoredVersionsAnAuditRow) {
  TempDir dir;
  const std::string path = dir.File("v4.db");
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ImportDataset(SimulatedMill(5, 24, 50)).ok());
    StatusOr<int64_t> id =
        store->EnqueueCalibration("nightly", WearLaw::kWang, 1);
    ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
    ASSERT_EQ(store->ActiveModel()->version, 1);
  }
  {
    StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)
                    ->Exec(std::string(testing::kUndoSchemaSixAndFive) +
                           "UPDATE schema_version SET version = 4")
                    .ok());
  }
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  StatusOr<std::vector<ModelPromotion>> h = store->ModelHistory(0);
  ASSERT_TRUE(h.ok());
  ASSERT_EQ(h->size(), 1u);
  EXPECT_EQ((*h)[0].version, 1);
  EXPECT_EQ((*h)[0].previous_version, 0);
  EXPECT_EQ((*h)[0].source, "nightly");
  EXPECT_EQ((*h)[0].reason, "recorded before the audit trail");
  EXPECT_EQ((*h)[0].at, store->ActiveModel()->created_at);
  EXPECT_FALSE(store->ActiveModel()->pinned);
}

TEST(StoreShopTest, RollLifeListsEachMountAndTheInventorySumsThem) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1'769'000'000)).ok());
  double f6_length_c1 = 0;
  for (int i = 0; i < 5; ++i) {
    const CoilIn c = MakeCoil("A" + std::to_string(i), "C1", i + 1, i);
    f6_length_c1 += c.passes[0].length_m;
    ASSERT_TRUE(store->AddCoil(c).ok());
  }
  const WearSnapshot end_c1 = Mounted(*store).Wear();  // F6 top first
  ASSERT_EQ(end_c1.positions.front().roll_id, "R6T");
  // C2 mounts the same rolls again (it ends C1).
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", 1'771'000'000)).ok());
  std::string suspect;
  ASSERT_TRUE(
      store
          ->AddMeasurement(
              MakeMeasurement("C1", 6, Position::kTop, "R6T", 42.5), &suspect)
          .ok());
  double f6_length_c2 = 0;
  for (int i = 0; i < 3; ++i) {
    const CoilIn c = MakeCoil("B" + std::to_string(i), "C2", i + 1, 9000 + i);
    f6_length_c2 += c.passes[0].length_m;
    ASSERT_TRUE(store->AddCoil(c).ok());
  }

  StatusOr<RollLife> life = store->GetRollLife("R6T");
  ASSERT_TRUE(life.ok()) << life.status().ToString();
  EXPECT_EQ(life->roll_type, "ICDP-S3");
  ASSERT_EQ(life->mounts.size(), 2u);
  const RollMountLife& m1 = life->mounts[0];
  EXPECT_EQ(m1.campaign_id, "C1");
  EXPECT_EQ(m1.stand, 6);
  EXPECT_EQ(m1.position, Position::kTop);
  EXPECT_EQ(m1.started_at, 1'769'000'000);
  ASSERT_TRUE(m1.ended_at.has_value());
  EXPECT_EQ(*m1.ended_at, 1'771'000'000);
  EXPECT_EQ(m1.coils, 5);
  EXPECT_LE(RelDiff(m1.rolled_length_m, f6_length_c1), 1e-12);
  // The replay of the ended mount is the live prediction it ended with.
  EXPECT_LE(
      RelDiff(m1.predicted_wear_um, end_c1.positions.front().predicted_wear_um),
      1e-12);
  EXPECT_GT(m1.predicted_wear_um, 0);
  ASSERT_TRUE(m1.measured_um.has_value());
  EXPECT_EQ(*m1.measured_um, 42.5);
  EXPECT_EQ(m1.measured_suspect, suspect);
  EXPECT_EQ(m1.diameter_mm, 700.5);
  const RollMountLife& m2 = life->mounts[1];
  EXPECT_EQ(m2.campaign_id, "C2");
  EXPECT_FALSE(m2.ended_at.has_value());
  EXPECT_EQ(m2.coils, 3);
  EXPECT_LE(RelDiff(m2.rolled_length_m, f6_length_c2), 1e-12);
  EXPECT_EQ(m2.predicted_wear_um,
            Mounted(*store).WearAt(6, Position::kTop)->predicted_wear_um);
  EXPECT_FALSE(m2.measured_um.has_value());

  EXPECT_EQ(store->GetRollLife("NOPE").status().code(), StatusCode::kNotFound);

  StatusOr<std::vector<RollSummary>> inv = store->RollInventory();
  ASSERT_TRUE(inv.ok());
  ASSERT_EQ(inv->size(), 4u);  // R6B, R6T, R7B, R7T
  const RollSummary& r6t = (*inv)[1];
  EXPECT_EQ(r6t.roll_id, "R6T");
  EXPECT_EQ(r6t.campaigns, 2);
  EXPECT_LE(RelDiff(r6t.total_rolled_m, f6_length_c1 + f6_length_c2), 1e-12);
  ASSERT_TRUE(r6t.last_measured_um.has_value());
  EXPECT_EQ(*r6t.last_measured_um, 42.5);
  EXPECT_TRUE(r6t.mounted);
  EXPECT_EQ(r6t.stand, 6);
  EXPECT_EQ(r6t.campaign_id, "C2");
  EXPECT_FALSE((*inv)[0].last_measured_um.has_value());  // R6B

  // Once C2 ends nothing is mounted.
  ASSERT_TRUE(store->EndCampaign("C2", 1'772'000'000).ok());
  EXPECT_FALSE((*store->RollInventory())[1].mounted);
  EXPECT_EQ(store->GetRollLife("R6T")->mounts[1].predicted_wear_um,
            m2.predicted_wear_um);
}

TEST(StoreShopTest, FinishedDiagnosesAreReadBackAfterRestart) {
  TempDir dir;
  StoredDiagnosis d;
  d.id = 3;
  d.status = "done";
  d.adopt = true;
  d.queued_at = 1'780'000'000;
  d.started_at = 1'780'000'001;
  d.finished_at = 1'780'000'060;
  d.verdict = "no_significant_mismatch";
  d.report_json = R"({"verdict":"no_significant_mismatch"})";
  d.report_html = "<html>report</html>";
  {
    auto store = OpenStore(dir.File("mill.db"));
    ASSERT_NE(store, nullptr);
    EXPECT_EQ(*store->LastDiagnosisId(), 0);
    StoredDiagnosis bad = d;
    bad.status = "running";
    EXPECT_EQ(store->SaveDiagnosis(bad).code(), StatusCode::kInvalidArgument);
    ASSERT_TRUE(store->SaveDiagnosis(d).ok());
    StoredDiagnosis failed;
    failed.id = 4;
    failed.status = "failed";
    failed.queued_at = failed.finished_at = 1'780'000'100;
    failed.message = "no measured campaign";
    ASSERT_TRUE(store->SaveDiagnosis(failed).ok());
  }
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(*store->LastDiagnosisId(), 4);
  auto got = store->GetDiagnosis(3);
  ASSERT_TRUE(got.ok());
  ASSERT_TRUE(got->has_value());
  EXPECT_EQ((*got)->verdict, d.verdict);
  EXPECT_EQ((*got)->report_json, d.report_json);
  EXPECT_EQ((*got)->report_html, d.report_html);
  EXPECT_EQ((*got)->finished_at, d.finished_at);
  EXPECT_TRUE((*got)->adopt);
  EXPECT_FALSE(store->GetDiagnosis(5)->has_value());
  auto list = store->ListDiagnoses(0);
  ASSERT_TRUE(list.ok());
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[0].id, 4);
  EXPECT_EQ((*list)[0].message, "no measured campaign");
  EXPECT_TRUE((*list)[1].report_json.empty());  // lists carry no report
}

}  // namespace
}  // namespace rollwear::storage
