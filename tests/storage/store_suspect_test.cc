// Suspect measurements in the store (docs/data-format.md, "Implausible
// values"): a finite reading that cannot be physical wear is stored
// flagged, not refused; the flag survives a reopen and answers repeats;
// imports store core's flags; calibration and diagnosis read the data
// without them (ReadFittingData); a version-3 file gains the column and
// keeps its rows.
#include <string>

#include <gtest/gtest.h>

#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "storage/store_sql.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::OpenStore;
using testing::SimulatedMill;
using testing::TempDir;

constexpr UnixSeconds kSuspectStart = 1'769'000'000;
constexpr UnixSeconds kSuspectEnd = 1'775'000'000;

std::unique_ptr<Db> MustOpen(const std::string& path) {
  StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  return db.ok() ? std::move(db).value() : nullptr;
}

std::string QueryText(Db* db, const std::string& sql) {
  StatusOr<Statement> st = db->Prepare(sql);
  EXPECT_TRUE(st.ok()) << sql;
  if (!st.ok()) return "<error>";
  StatusOr<bool> row = st->Step();
  if (!row.ok() || !*row) return "<no row>";
  return st->ColumnIsNull(0) ? "<null>" : st->ColumnText(0);
}

// One ended campaign C1 with 30 coils on F6/F7, nothing measured.
void StoreEndedCampaign(MillStore* store) {
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", kSuspectStart)).ok());
  for (int i = 1; i <= 30; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i, i)).ok());
  }
  ASSERT_TRUE(store->EndCampaign("C1", kSuspectEnd).ok());
}

TEST(StoreSuspectTest, NegativeReadingIsStoredFlaggedAndAnsweredOnRepeat) {
  TempDir dir;
  const std::string path = dir.File("mill.db");
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  StoreEndedCampaign(store.get());
  // Under 8 readings the bound is core's fixed one: -4 * 12.5 = -50 µm.
  const MeasurementIn bad =
      MakeMeasurement("C1", 6, Position::kTop, "R6T", -62.6);
  std::string suspect;
  StatusOr<WriteOutcome> out = store->AddMeasurement(bad, &suspect);
  ASSERT_TRUE(out.ok()) << out.status().ToString();
  EXPECT_EQ(*out, WriteOutcome::kCreated);
  EXPECT_EQ(suspect.rfind("negative_wear: -62.6 µm is below -50.0 µm", 0), 0u)
      << suspect;
  // -40 µm is within the gauge's noise bound: stored unflagged.
  std::string fine = "x";
  ASSERT_TRUE(
      store
          ->AddMeasurement(
              MakeMeasurement("C1", 6, Position::kBottom, "R6B", -40), &fine)
          .ok());
  EXPECT_EQ(fine, "");
  EXPECT_EQ(store->Counters().measurements, 2);
  // A repeat answers the stored flag, also after a reopen.
  std::string again;
  out = store->AddMeasurement(bad, &again);
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(*out, WriteOutcome::kUnchanged);
  EXPECT_EQ(again, suspect);
  store.reset();
  store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  again.clear();
  ASSERT_TRUE(store->AddMeasurement(bad, &again).ok());
  EXPECT_EQ(again, suspect);
  store.reset();
  auto db = MustOpen(path);
  EXPECT_EQ(QueryText(db.get(),
                      "SELECT suspect FROM measurements WHERE "
                      "wear_center_um = -62.6"),
            suspect);
  EXPECT_EQ(QueryText(db.get(),
                      "SELECT suspect FROM measurements WHERE "
                      "wear_center_um = -40"),
            "<null>");
}

TEST(StoreSuspectTest, NonFiniteReadingIsStillRefused) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  StoreEndedCampaign(store.get());
  StatusOr<WriteOutcome> out = store->AddMeasurement(
      MakeMeasurement("C1", 6, Position::kTop, "R6T", INFINITY));
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(store->Counters().measurements, 0);
}

// A paper-like mill: 60 campaigns imported with one gauge fault (-62.6
// µm), then a reading far beyond what its campaign could produce posted.
// Both are stored flagged and neither is fitted.
TEST(StoreSuspectTest, ImportAndPostFlagsAreLeftOutOfFitting) {
  TempDir dir;
  const std::string path = dir.File("mill.db");
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  Dataset data = SimulatedMill(11, 60, 60);
  const size_t n = data.measurements.size();
  ASSERT_GT(n, 100u);
  data.measurements[17].wear_center_um = -62.6;
  ASSERT_TRUE(store->ImportDataset(data).ok());
  EXPECT_EQ(store->Counters().measurements, static_cast<int64_t>(n));

  ASSERT_TRUE(
      store->ApplyRollChange(MakeRollChange("NEW", 1'900'000'000)).ok());
  for (int i = 1; i <= 30; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("N" + std::to_string(i), "NEW", i, i)).ok());
  }
  ASSERT_TRUE(store->EndCampaign("NEW", 1'900'100'000).ok());
  MeasurementIn huge = MakeMeasurement("NEW", 7, Position::kTop, "R7T", 9000);
  huge.measured_at = 1'900'200'000;
  std::string suspect;
  ASSERT_TRUE(store->AddMeasurement(huge, &suspect).ok());
  EXPECT_EQ(suspect.rfind("excess_wear: 9000.0 µm is far beyond", 0), 0u)
      << suspect;

  StatusOr<FittingData> fitting = store->ReadFittingData();
  ASSERT_TRUE(fitting.ok()) << fitting.status().ToString();
  EXPECT_EQ(fitting->all.measurements.size(), n + 1);
  EXPECT_EQ(fitting->fit.measurements.size(), n - 1);
  EXPECT_EQ(fitting->quality.NumSuspect(), 2);
  EXPECT_EQ(fitting->quality.Count(DataQualityKind::kNegativeWear), 1);
  EXPECT_EQ(fitting->quality.Count(DataQualityKind::kExcessWear), 1);
  for (const Measurement& m : fitting->fit.measurements) {
    EXPECT_GT(m.wear_center_um, -50);
    EXPECT_LT(m.wear_center_um, 9000);
  }
  // A calibration scores exactly the measured rolls that are not suspect.
  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  StatusOr<CalibrationRecord> rec = store->GetCalibration(*id);
  ASSERT_TRUE(rec.ok());
  EXPECT_EQ(rec->status, CalibrationStatus::kDone) << rec->message;
  EXPECT_EQ(rec->n_train + rec->n_val, static_cast<int>(n - 1));

  store.reset();
  auto db = MustOpen(path);
  EXPECT_EQ(QueryText(db.get(),
                      "SELECT COUNT(*) FROM measurements WHERE "
                      "suspect IS NOT NULL"),
            "2");
  EXPECT_EQ(QueryText(db.get(),
                      "SELECT substr(suspect, 1, 14) FROM "
                      "measurements WHERE wear_center_um = -62.6"),
            "negative_wear:");
}

// A version-3 file (no measurements.suspect) is migrated on open: the
// column is added, its rows are kept unflagged and answer repeats as before.
TEST(StoreSuspectTest, VersionThreeFileGainsTheColumnAndKeepsItsRows) {
  TempDir dir;
  const std::string path = dir.File("v3.db");
  const MeasurementIn m =
      MakeMeasurement("C1", 7, Position::kTop, "R7T", 180.25);
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    StoreEndedCampaign(store.get());
    ASSERT_TRUE(store->AddMeasurement(m).ok());
  }
  {
    auto db = MustOpen(path);
    ASSERT_TRUE(db->Exec(std::string(testing::kUndoSchemaSixAndFive) +
                         "ALTER TABLE measurements DROP COLUMN suspect; "
                         "UPDATE schema_version SET version = 3")
                    .ok());
    EXPECT_EQ(QueryText(db.get(),
                        "SELECT COUNT(*) FROM pragma_table_info("
                        "'measurements') WHERE name = 'suspect'"),
              "0");
  }
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->Counters().measurements, 1);
  EXPECT_EQ(store->Counters().coils, 30);
  std::string suspect = "x";
  StatusOr<WriteOutcome> out = store->AddMeasurement(m, &suspect);
  ASSERT_TRUE(out.ok()) << out.status().ToString();
  EXPECT_EQ(*out, WriteOutcome::kUnchanged);
  EXPECT_EQ(suspect, "");
  store.reset();
  auto db = MustOpen(path);
  EXPECT_EQ(QueryText(db.get(), "SELECT version FROM schema_version"),
            std::to_string(kSchemaVersion));
  EXPECT_EQ(QueryText(db.get(),
                      "SELECT wear_center_um || ' ' || "
                      "coalesce(suspect, 'null') FROM measurements"),
            "180.25 null");
}

}  // namespace
}  // namespace rollwear::storage
