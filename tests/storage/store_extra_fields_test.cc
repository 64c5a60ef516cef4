// Extra fields of API records (ExtraFields on RollChangeIn, MountedRollIn,
// CoilIn, PassIn, MeasurementIn) on a real SQLite file: stored in their
// rows' `extra` column as an imported folder's extra columns are, part of
// the content idempotent repeats compare, and the values of terms adopted
// on extra columns - the live wear equals the diagnosis engine's batch
// prediction of the same data, before and after a restart.
#include <cmath>

#include <gtest/gtest.h>

#include "core/fit/term_fit.h"
#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "storage/model_levels.h"
#include "tests/core/extra_terms_util.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using extra_terms_test::AddExtraColumns;
using extra_terms_test::BatchPrediction;
using extra_terms_test::ExtraTerms;
using extra_terms_test::ModelWithTerms;
using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::RelDiff;
using testing::SimulatedMill;
using testing::TempDir;

constexpr UnixSeconds kOpenStart = 1'900'000'000;

// The open campaign's roll change: crew B; rolls with supplier Y, X, none
// (an empty cell) and Z (a level the terms never saw).
RollChangeIn OpenRollChange() {
  RollChangeIn rc = MakeRollChange("OPEN", kOpenStart);
  rc.extra.factor = {{"crew", "B"}};
  rc.rolls[0].extra.factor = {{"supplier", "Y"}};
  rc.rolls[1].extra.factor = {{"supplier", "X"}};
  rc.rolls[3].extra.factor = {{"supplier", "Z"}};
  return rc;
}

// Coil i: coolant pressure for the whole coil, per pass, or not at all.
CoilIn OpenCoil(int i) {
  CoilIn c = MakeCoil("OC" + std::to_string(i), "OPEN", i + 1, i);
  if (i % 3 == 0) {
    c.extra.numeric = {{"coolant_bar", 2.0 + 0.01 * i}};
  } else if (i % 3 == 1) {
    c.passes[0].extra.numeric = {{"coolant_bar", 2.25}};
    c.passes[1].extra.numeric = {{"coolant_bar", 2.4 - 0.005 * i}};
  }
  return c;
}

// The live wear of the open campaign against the batch prediction of the
// exported data (the open campaign's rolls given a placeholder measurement
// so that they are observations), with and without the terms.
void ExpectLiveWearIsBatch(const MillStore& store) {
  StatusOr<Dataset> data = store.ExportDataset();
  ASSERT_TRUE(data.ok()) << data.status().ToString();
  Dataset d = *data;
  const int open = static_cast<int>(d.campaigns.size()) - 1;
  ASSERT_EQ(d.campaigns[open].id, "OPEN");
  for (const Mount& m : d.mounts) {
    if (m.campaign != open) continue;
    d.measurements.push_back(
        {open, m.stand, m.position, m.roll_id, kOpenStart + 86400, 100.0});
    for (auto& col : d.measurement_extra.numeric) col.push_back(std::nan(""));
  }
  StatusOr<TermData> td = BuildTermData(d, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  StatusOr<ModelVersion> active = store.ActiveModel();
  ASSERT_TRUE(active.ok());
  StatusOr<WearModel> model = ModelOverLevels(active->wear_model, td->positions,
                                              td->roll_types, td->grades);
  ASSERT_TRUE(model.ok());
  const std::vector<double> batch = BatchPrediction(*td, *model, true);
  WearModel bare = *model;
  bare.terms.clear();
  const std::vector<double> batch_bare = BatchPrediction(*td, bare, true);
  const WearSnapshot snap = Mounted(store).Wear();
  int compared = 0;
  for (size_t o = 0; o < td->obs.size(); ++o) {
    if (td->obs[o].campaign != open) continue;
    for (const PositionWear& w : snap.positions) {
      if (RollPositionSlot(w.stand, w.position) != td->obs[o].slot) continue;
      EXPECT_LE(RelDiff(w.predicted_wear_um, batch[o]), 1e-8)
          << RollPositionName(w.stand, w.position) << ": live "
          << w.predicted_wear_um << " batch " << batch[o];
      EXPECT_GT(std::abs(batch[o] / batch_bare[o] - 1), 0.01);
      ++compared;
    }
  }
  EXPECT_EQ(compared, 4);
}

TEST(StoreExtraFieldsTest, TermsOnExtraFieldsRunLiveAsInBatchAcrossRestarts) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  // A mill whose readings follow a model with terms on its extra columns.
  Dataset mill = SimulatedMill(31, 24, 40);
  AddExtraColumns(&mill);
  StatusOr<TermData> td = BuildTermData(mill, WearLaw::kWang);
  ASSERT_TRUE(td.ok());
  const WearModel truth = ModelWithTerms(*td, ExtraTerms());
  const std::vector<double> reading = BatchPrediction(*td, truth, false);
  for (size_t o = 0; o < td->obs.size(); ++o) {
    mill.measurements[td->obs[o].measurement].wear_center_um = reading[o];
  }
  ASSERT_TRUE(store->ImportDataset(mill).ok());
  StatusOr<CalibrationRecord> run = engine::CalibrationRuns(&*store).Propose(
      "test", "wang", 1, truth, mill, 1);
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  ASSERT_TRUE(run->promoted) << run->message;
  EXPECT_LT(run->gap_val_um, 1e-6);  // scored coil by coil with the terms
  EXPECT_EQ(store->ActiveModel()->wear_model.terms[1].levels,
            (std::vector<std::string>{"A", "B", ""}));

  ASSERT_EQ(*store->ApplyRollChange(OpenRollChange()), WriteOutcome::kCreated);
  for (int i = 0; i < 30; ++i) {
    StatusOr<CoilOutcome> out = store->AddCoil(OpenCoil(i));
    ASSERT_TRUE(out.ok()) << out.status().ToString();
    EXPECT_EQ(out->outcome, WriteOutcome::kCreated);
  }
  ExpectLiveWearIsBatch(*store);

  // Stored as an imported folder's columns would be: a missing field is an
  // empty cell (NaN, the empty level).
  StatusOr<Dataset> out = store->ExportDataset();
  ASSERT_TRUE(out.ok());
  ASSERT_EQ(out->pass_extra.numeric_names,
            std::vector<std::string>{"coolant_bar"});
  const std::vector<double>& coolant = out->pass_extra.numeric[0];
  const size_t first = mill.passes.size();  // the open campaign's rows
  ASSERT_EQ(coolant.size(), first + 60);
  EXPECT_EQ(coolant[first + 0], 2.0);  // coil 0, F6 (coil-level field)
  EXPECT_EQ(coolant[first + 1], 2.0);  // coil 0, F7
  EXPECT_EQ(coolant[first + 2], 2.25);
  EXPECT_EQ(coolant[first + 3], 2.4 - 0.005);
  EXPECT_TRUE(std::isnan(coolant[first + 4]));  // coil 2: none
  const ExtraColumns& mounts = out->mount_extra;
  ASSERT_EQ(mounts.factor_names, std::vector<std::string>{"supplier"});
  const size_t m0 = mill.mounts.size();
  const auto level = [&](size_t row) {
    return mounts.factor_levels[0][mounts.factor[0][row]];
  };
  EXPECT_EQ(level(m0 + 0), "Y");
  EXPECT_EQ(level(m0 + 2), "");
  EXPECT_EQ(level(m0 + 3), "Z");
  EXPECT_EQ(out->campaign_extra
                .factor_levels[0][out->campaign_extra.factor[0].back()],
            "B");

  // Repeats: the same fields are unchanged (a coil-level field is each
  // pass's field), another value, a dropped or an added field conflict.
  EXPECT_EQ(store->AddCoil(OpenCoil(0))->outcome, WriteOutcome::kUnchanged);
  CoilIn per_pass = OpenCoil(0);
  for (PassIn& p : per_pass.passes) p.extra = per_pass.extra;
  per_pass.extra = {};
  EXPECT_EQ(store->AddCoil(per_pass)->outcome, WriteOutcome::kUnchanged);
  CoilIn other = OpenCoil(0);
  other.extra.numeric[0].second += 1e-9;
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  other = OpenCoil(0);
  other.extra = {};
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  other = OpenCoil(2);
  other.passes[1].extra.factor = {{"shift_crew", "night"}};
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(*store->ApplyRollChange(OpenRollChange()),
            WriteOutcome::kUnchanged);
  RollChangeIn rc = OpenRollChange();
  rc.extra.factor[0].second = "A";
  EXPECT_EQ(store->ApplyRollChange(rc).status().code(),
            StatusCode::kAlreadyExists);
  rc = OpenRollChange();
  rc.rolls[2].extra.factor = {{"supplier", "X"}};
  EXPECT_EQ(store->ApplyRollChange(rc).status().code(),
            StatusCode::kAlreadyExists);
  EXPECT_EQ(store->Counters().coils,
            static_cast<int64_t>(mill.coil_ids.size()) + 30);

  // Restart: the fields are read back and give the same wear, bit for bit;
  // repeats are judged the same way.
  const WearSnapshot before = Mounted(*store).Wear();
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const WearSnapshot after = Mounted(*store).Wear();
  ASSERT_EQ(after.positions.size(), 4u);
  for (size_t i = 0; i < after.positions.size(); ++i) {
    EXPECT_EQ(after.positions[i].predicted_wear_um,
              before.positions[i].predicted_wear_um);
  }
  EXPECT_EQ(store->AddCoil(OpenCoil(1))->outcome, WriteOutcome::kUnchanged);
  other = OpenCoil(1);
  other.passes[0].extra = {};
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(*store->ApplyRollChange(OpenRollChange()),
            WriteOutcome::kUnchanged);
  EXPECT_EQ(store->ApplyRollChange(rc).status().code(),
            StatusCode::kAlreadyExists);
  // More coils after the restart, still as the batch.
  for (int i = 30; i < 36; ++i) ASSERT_TRUE(store->AddCoil(OpenCoil(i)).ok());
  ExpectLiveWearIsBatch(*store);

  // A measurement's field drives the measurement term on the dashboard:
  // expected reading = wear + 4 * (36 - 30) / 5.
  ASSERT_TRUE(store->EndCampaign("OPEN", kOpenStart + 7200).ok());
  MeasurementIn me = MakeMeasurement("OPEN", 6, Position::kTop, "R6T", 50);
  me.measured_at = kOpenStart + 7200 + 3600;  // an hour after the end
  me.extra.numeric = {{"probe_temp_c", 36}};
  StatusOr<WriteOutcome> created = store->AddMeasurement(me);
  ASSERT_TRUE(created.ok()) << created.status().message();
  EXPECT_EQ(*created, WriteOutcome::kCreated);
  StatusOr<WriteOutcome> again = store->AddMeasurement(me);
  ASSERT_TRUE(again.ok()) << again.status().message();
  EXPECT_EQ(*again, WriteOutcome::kUnchanged);
  MeasurementIn me2 = me;
  me2.extra.numeric[0].second = 37;
  EXPECT_EQ(store->AddMeasurement(me2).status().code(),
            StatusCode::kAlreadyExists);
  me2.extra = {};
  EXPECT_EQ(store->AddMeasurement(me2).status().code(),
            StatusCode::kAlreadyExists);
  StatusOr<std::vector<CampaignWearHistory>> hist = store->RecentWear(1);
  ASSERT_TRUE(hist.ok());
  ASSERT_FALSE(hist->empty());
  ASSERT_EQ(hist->front().campaign_id, "OPEN");
  bool checked = false;
  for (const RollWearHistory& h : hist->front().rolls) {
    if (h.stand != 6 || h.position != Position::kTop) continue;
    EXPECT_NEAR(h.expected_reading_um - h.final_predicted_um, 4.8, 1e-9);
    EXPECT_GT(h.final_predicted_um, before.positions[0].predicted_wear_um);
    checked = true;
  }
  EXPECT_TRUE(checked);
}

}  // namespace
}  // namespace rollwear::storage
