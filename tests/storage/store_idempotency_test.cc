// Idempotent POSTs for the four keys: the same content again is kUnchanged
// (nothing counted twice, whatever happened since, also after a restart);
// other content under the same key is AlreadyExists.
#include <gtest/gtest.h>

#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

TEST(StoreIdempotencyTest, RollChange) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const RollChangeIn c1 = MakeRollChange("C1", 1000);
  ASSERT_EQ(*store->ApplyRollChange(c1), WriteOutcome::kCreated);
  ASSERT_TRUE(store->AddCoil(MakeCoil("K1", "C1", 1)).ok());
  EXPECT_EQ(*store->ApplyRollChange(c1), WriteOutcome::kUnchanged);
  // Roll order does not matter; content does.
  RollChangeIn reordered = c1;
  std::swap(reordered.rolls[0], reordered.rolls[3]);
  EXPECT_EQ(*store->ApplyRollChange(reordered), WriteOutcome::kUnchanged);
  RollChangeIn other = c1;
  other.rolls[2].diameter_mm += 1e-9;
  EXPECT_EQ(store->ApplyRollChange(other).status().code(),
            StatusCode::kAlreadyExists);
  other = c1;
  other.started_at += 1;
  EXPECT_EQ(store->ApplyRollChange(other).status().code(),
            StatusCode::kAlreadyExists);
  other = c1;
  other.rolls.pop_back();
  EXPECT_EQ(store->ApplyRollChange(other).status().code(),
            StatusCode::kAlreadyExists);
  // Whatever has happened since: C1 ended by C2, still unchanged, and it
  // neither reopens C1 nor ends C2.
  ASSERT_EQ(*store->ApplyRollChange(MakeRollChange("C2", 5000, "2")),
            WriteOutcome::kCreated);
  EXPECT_EQ(*store->ApplyRollChange(c1), WriteOutcome::kUnchanged);
  EXPECT_EQ(Mounted(*store).Wear().positions.front().campaign_id, "C2");
  EXPECT_EQ(store->Counters().campaigns, 2);
  // And after a restart.
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(*store->ApplyRollChange(c1), WriteOutcome::kUnchanged);
  EXPECT_EQ(store->ApplyRollChange(other).status().code(),
            StatusCode::kAlreadyExists);
  EXPECT_EQ(store->Counters().campaigns, 2);
}

TEST(StoreIdempotencyTest, CampaignEnd) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  ASSERT_EQ(*store->EndCampaign("C1", 4000), WriteOutcome::kCreated);
  EXPECT_EQ(*store->EndCampaign("C1", 4000), WriteOutcome::kUnchanged);
  EXPECT_EQ(store->EndCampaign("C1", 4001).status().code(),
            StatusCode::kAlreadyExists);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", 5000, "2")).ok());
  // C2's roll change ends nothing (C1 already ended); C1's end unchanged.
  EXPECT_EQ(*store->EndCampaign("C1", 4000), WriteOutcome::kUnchanged);
  EXPECT_EQ(Mounted(*store).Wear().positions.size(), 4u);
  // A campaign ended by the next roll change: the same time is unchanged.
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C3", 7000, "3")).ok());
  EXPECT_EQ(*store->EndCampaign("C2", 7000), WriteOutcome::kUnchanged);
  EXPECT_EQ(store->EndCampaign("C2", 6500).status().code(),
            StatusCode::kAlreadyExists);
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(*store->EndCampaign("C1", 4000), WriteOutcome::kUnchanged);
  EXPECT_EQ(store->EndCampaign("C1", 1).status().code(),
            StatusCode::kAlreadyExists);
}

TEST(StoreIdempotencyTest, Coil) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  const CoilIn k1 = MakeCoil("K1", "C1", 1, 5);
  StatusOr<CoilOutcome> first = store->AddCoil(k1);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->outcome, WriteOutcome::kCreated);
  ASSERT_TRUE(store->AddCoil(MakeCoil("K2", "C1", 2, 6)).ok());
  const double wear = Mounted(*store).Wear().positions[0].predicted_wear_um;

  StatusOr<CoilOutcome> again = store->AddCoil(k1);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->outcome, WriteOutcome::kUnchanged);
  ASSERT_EQ(again->added.size(), first->added.size());
  EXPECT_EQ(again->added[0].wear_um, first->added[0].wear_um);
  // The first answer: the roll's total right after K1, not the current one.
  EXPECT_EQ(again->added[0].predicted_wear_um,
            first->added[0].predicted_wear_um);
  EXPECT_LT(again->added[0].predicted_wear_um, wear);
  EXPECT_EQ(Mounted(*store).Wear().positions[0].predicted_wear_um, wear);
  EXPECT_EQ(Mounted(*store).Wear().positions[0].coils, 2);
  // Pass order does not matter.
  CoilIn reordered = k1;
  std::swap(reordered.passes[0], reordered.passes[1]);
  EXPECT_EQ(store->AddCoil(reordered)->outcome, WriteOutcome::kUnchanged);
  // Any difference is a conflict, even in the last bit.
  CoilIn other = k1;
  other.passes[1].force_kn = std::nextafter(other.passes[1].force_kn, 1e9);
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  other = k1;
  other.grade = "X";
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  other = k1;
  other.passes.pop_back();
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  other = k1;
  other.campaign_id = "C9";  // the key wins over the unknown campaign
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(store->Counters().coils, 2);

  // After the campaign ended (a new coil would be refused) and a restart.
  ASSERT_TRUE(store->EndCampaign("C1", 9000).ok());
  again = store->AddCoil(k1);
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(again->outcome, WriteOutcome::kUnchanged);
  EXPECT_EQ(again->added[0].predicted_wear_um,
            first->added[0].predicted_wear_um);
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->AddCoil(k1)->outcome, WriteOutcome::kUnchanged);
  EXPECT_EQ(store->AddCoil(other).status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(store->Counters().coils, 2);
}

TEST(StoreIdempotencyTest, Measurement) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  ASSERT_TRUE(store->EndCampaign("C1", 2000).ok());
  const MeasurementIn m =
      MakeMeasurement("C1", 7, Position::kBottom, "R7B", 123.25);
  ASSERT_EQ(*store->AddMeasurement(m), WriteOutcome::kCreated);
  EXPECT_EQ(*store->AddMeasurement(m), WriteOutcome::kUnchanged);
  MeasurementIn other = m;
  other.wear_center_um = 123.5;
  EXPECT_EQ(store->AddMeasurement(other).status().code(),
            StatusCode::kAlreadyExists);
  other = m;
  other.measured_at += 60;
  EXPECT_EQ(store->AddMeasurement(other).status().code(),
            StatusCode::kAlreadyExists);
  EXPECT_EQ(store->Counters().measurements, 1);
  EXPECT_EQ(store->Counters().measurements_since_last_calibration, 1);
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(*store->AddMeasurement(m), WriteOutcome::kUnchanged);
  EXPECT_EQ(store->AddMeasurement(other).status().code(),
            StatusCode::kAlreadyExists);
  EXPECT_EQ(store->Counters().measurements, 1);
  EXPECT_EQ(store->Counters().measurements_since_last_calibration, 1);
}

}  // namespace
}  // namespace rollwear::storage
