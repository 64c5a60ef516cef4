// MillStore on a real SQLite file: opening, the life of a campaign (roll
// change, coils, end, measurements), the live wear against the batch
// prediction, and restart (reopening gives exactly the same state).
#include <cstring>

#include <gtest/gtest.h>

#include "engine/wear_prediction.h"
#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::BitEqual;

using testing::ExpectWearMatchesBatch;
using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

void ExpectSameSnapshot(const WearSnapshot& a, const WearSnapshot& b) {
  EXPECT_EQ(a.model_version, b.model_version);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (size_t i = 0; i < a.positions.size(); ++i) {
    const PositionWear &x = a.positions[i], &y = b.positions[i];
    EXPECT_EQ(x.stand, y.stand);
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.roll_id, y.roll_id);
    EXPECT_EQ(x.roll_type, y.roll_type);
    EXPECT_EQ(x.campaign_id, y.campaign_id);
    EXPECT_EQ(x.coils, y.coils);
    EXPECT_TRUE(BitEqual(x.rolled_length_m, y.rolled_length_m));
    EXPECT_TRUE(BitEqual(x.predicted_wear_um, y.predicted_wear_um))
        << x.predicted_wear_um << " vs " << y.predicted_wear_um;
    EXPECT_TRUE(BitEqual(x.interval_lo_um, y.interval_lo_um));
    EXPECT_TRUE(BitEqual(x.interval_hi_um, y.interval_hi_um));
  }
}

TEST(StoreBasicTest, OpensAnEmptyStore) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_TRUE(store->Healthy());
  const StoreCounters n = store->Counters();
  EXPECT_EQ(n.coils, 0);
  EXPECT_EQ(n.campaigns, 0);
  EXPECT_EQ(n.measurements, 0);
  EXPECT_EQ(n.commits, 0);
  EXPECT_TRUE(Mounted(*store).Wear().positions.empty());
  StatusOr<ModelVersion> active = store->ActiveModel();
  ASSERT_TRUE(active.ok());
  EXPECT_EQ(active->version, 0);
  EXPECT_EQ(active->model, "wang");
  EXPECT_TRUE(store->ListModels().empty());
  EXPECT_EQ(Mounted(*store).WearAt(6, Position::kTop).status().code(),
            StatusCode::kNotFound);
  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  EXPECT_TRUE(data->campaigns.empty());
}

TEST(StoreBasicTest, InvalidOptionsAreRefused) {
  TempDir dir;
  StoreOptions o;
  o.default_option = 4;
  StatusOr<std::unique_ptr<MillStore>> s =
      engine::OpenStore(dir.File("x.db"), o);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), StatusCode::kInvalidArgument);
}

// The store computes no prediction itself: opened without the engine's
// predictor it refuses, and says where to get one.
TEST(StoreBasicTest, AStoreWithoutAPredictorIsRefused) {
  TempDir dir;
  StatusOr<std::unique_ptr<MillStore>> s =
      MillStore::Open(dir.File("x.db"), StoreOptions());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.status().message().find("engine::OpenStore"), std::string::npos)
      << s.status().ToString();
  EXPECT_TRUE(engine::OpenStore(dir.File("x.db")).ok());
}

TEST(StoreBasicTest, CoilsAddWearToTheMountedRollsLikeTheBatchPrediction) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  StatusOr<WriteOutcome> rc =
      store->ApplyRollChange(MakeRollChange("C1", 1000));
  ASSERT_TRUE(rc.ok()) << rc.status().ToString();
  EXPECT_EQ(*rc, WriteOutcome::kCreated);
  // The prior model now covers the positions seen, kF = initial_k.
  StatusOr<ModelVersion> prior = store->ActiveModel();
  ASSERT_TRUE(prior.ok());
  EXPECT_EQ(prior->wear_model.structure.positions().size(), 4u);
  EXPECT_EQ(prior->wear_model.k[0], 0.3);

  double total_f6_top = 0;
  for (int i = 0; i < 50; ++i) {
    StatusOr<CoilOutcome> out =
        store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i + 1, i));
    ASSERT_TRUE(out.ok()) << out.status().ToString();
    EXPECT_EQ(out->outcome, WriteOutcome::kCreated);
    ASSERT_EQ(out->added.size(), 4u);  // F6 and F7, top and bottom
    EXPECT_EQ(out->added[0].stand, 6);
    EXPECT_EQ(out->added[0].position, Position::kTop);
    EXPECT_EQ(out->added[0].roll_id, "R6T");
    EXPECT_GT(out->added[0].wear_um, 0);
    total_f6_top += out->added[0].wear_um;
    EXPECT_NEAR(out->added[0].predicted_wear_um, total_f6_top,
                1e-9 * total_f6_top);
  }
  const WearSnapshot snap = Mounted(*store).Wear();
  ASSERT_EQ(snap.positions.size(), 4u);
  EXPECT_EQ(snap.positions[0].stand, 6);
  EXPECT_EQ(snap.positions[0].position, Position::kTop);
  EXPECT_EQ(snap.positions[1].position, Position::kBottom);
  EXPECT_EQ(snap.positions[2].stand, 7);
  EXPECT_EQ(snap.positions[0].coils, 50);
  EXPECT_EQ(snap.positions[0].campaign_id, "C1");
  ExpectWearMatchesBatch(*store);
  StatusOr<PositionWear> f7b = Mounted(*store).WearAt(7, Position::kBottom);
  ASSERT_TRUE(f7b.ok());
  EXPECT_EQ(f7b->roll_id, "R7B");
  EXPECT_EQ(store->Counters().coils, 50);
  EXPECT_EQ(store->Counters().campaigns, 1);
  EXPECT_LE(store->Counters().commits, 51);
}

TEST(StoreBasicTest, RollChangeEndsTheOpenCampaignAndEndClearsTheRolls) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  ASSERT_TRUE(store->AddCoil(MakeCoil("K1", "C1", 1)).ok());
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", 5000, "b")).ok());
  // C1 ended at C2's start: coils for it are refused now.
  StatusOr<CoilOutcome> late = store->AddCoil(MakeCoil("K2", "C1", 2));
  EXPECT_EQ(late.status().code(), StatusCode::kFailedPrecondition);
  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  ASSERT_EQ(data->campaigns.size(), 2u);
  EXPECT_EQ(data->campaigns[0].ended_at, 5000);
  const WearSnapshot snap = Mounted(*store).Wear();
  ASSERT_EQ(snap.positions.size(), 4u);
  EXPECT_EQ(snap.positions[0].campaign_id, "C2");
  EXPECT_EQ(snap.positions[0].coils, 0);
  EXPECT_EQ(snap.positions[0].predicted_wear_um, 0);

  ASSERT_TRUE(store->EndCampaign("C2", 9000).ok());
  EXPECT_TRUE(Mounted(*store).Wear().positions.empty());
  // Measurements of the ended campaigns are accepted.
  EXPECT_TRUE(store
                  ->AddMeasurement(
                      MakeMeasurement("C1", 6, Position::kTop, "R6T", 80.5))
                  .ok());
  EXPECT_TRUE(store
                  ->AddMeasurement(
                      MakeMeasurement("C2", 7, Position::kBottom, "R7Bb", 1))
                  .ok());
  const StoreCounters n = store->Counters();
  EXPECT_EQ(n.measurements, 2);
  EXPECT_EQ(n.measurements_since_last_calibration, 2);
  EXPECT_EQ(n.campaigns, 2);
}

TEST(StoreBasicTest, ReopeningRestoresExactlyTheSameState) {
  TempDir dir;
  WearSnapshot before;
  StoreCounters counters_before;
  StatusOr<Dataset> data_before = Status::Internal("unset");
  {
    auto store = OpenStore(dir.File("mill.db"));
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
    for (int i = 0; i < 30; ++i) {
      ASSERT_TRUE(
          store->AddCoil(MakeCoil("A" + std::to_string(i), "C1", i + 1, i))
              .ok());
    }
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", 90000, "x")).ok());
    ASSERT_TRUE(store
                    ->AddMeasurement(
                        MakeMeasurement("C1", 6, Position::kTop, "R6T", 55))
                    .ok());
    for (int i = 0; i < 40; ++i) {
      ASSERT_TRUE(store
                      ->AddCoil(MakeCoil("B" + std::to_string(i), "C2", i + 1,
                                         1000 + 7 * i))
                      .ok());
    }
    before = Mounted(*store).Wear();
    counters_before = store->Counters();
    data_before = store->ExportDataset();
    ASSERT_TRUE(data_before.ok());
  }
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ExpectSameSnapshot(before, Mounted(*store).Wear());
  const StoreCounters after = store->Counters();
  EXPECT_EQ(after.coils, counters_before.coils);
  EXPECT_EQ(after.campaigns, counters_before.campaigns);
  EXPECT_EQ(after.measurements, counters_before.measurements);
  EXPECT_EQ(after.measurements_since_last_calibration,
            counters_before.measurements_since_last_calibration);
  EXPECT_EQ(after.commits, 0);  // counts this process's transactions
  StatusOr<Dataset> data_after = store->ExportDataset();
  ASSERT_TRUE(data_after.ok());
  testing::ExpectSameDataset(*data_before, *data_after);
  ExpectWearMatchesBatch(*store);
  // The catalog came back too: the open campaign takes coils, keys repeat.
  EXPECT_EQ(store->AddCoil(MakeCoil("B0", "C2", 1, 1000))->outcome,
            WriteOutcome::kUnchanged);
  EXPECT_EQ(store->AddCoil(MakeCoil("B40", "C2", 5, 1)).status().code(),
            StatusCode::kFailedPrecondition);  // seq 5 is taken
  EXPECT_TRUE(store->AddCoil(MakeCoil("B40", "C2", 41, 1)).ok());
  EXPECT_EQ(store->AddCoil(MakeCoil("A31", "C1", 31, 1)).status().code(),
            StatusCode::kFailedPrecondition);  // C1 ended
}

}  // namespace
}  // namespace rollwear::storage
