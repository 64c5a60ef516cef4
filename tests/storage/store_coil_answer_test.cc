// A repeated coil is answered with its first answer, read from the coil's
// row (schema version 2, coils.wear): the same wear added and the same roll
// totals right after it, counted once - while its twin is queued, after the
// campaign ended, after a restart, after a model promotion; imported coils
// and coils of a version-1 file get their answers filled in.
#include <atomic>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

// Every field of the `added` lists, doubles compared exactly.
void ExpectSameAdded(const CoilOutcome& a, const CoilOutcome& b) {
  ASSERT_EQ(a.added.size(), b.added.size());
  for (size_t i = 0; i < a.added.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a.added[i].stand, b.added[i].stand);
    EXPECT_EQ(a.added[i].position, b.added[i].position);
    EXPECT_EQ(a.added[i].roll_id, b.added[i].roll_id);
    EXPECT_EQ(a.added[i].wear_um, b.added[i].wear_um);
    EXPECT_EQ(a.added[i].predicted_wear_um, b.added[i].predicted_wear_um);
  }
}

int64_t QueryInt(const std::string& path, const char* sql) {
  StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
  EXPECT_TRUE(db.ok());
  if (!db.ok()) return -1;
  StatusOr<Statement> st = (*db)->Prepare(sql);
  EXPECT_TRUE(st.ok()) << st.status().ToString();
  if (!st.ok()) return -1;
  StatusOr<bool> row = st->Step();
  EXPECT_TRUE(row.ok() && *row) << sql;
  return st->ColumnInt(0);
}

// Posts coils K1..Kn into the open campaign C1; returns their answers.
std::vector<CoilOutcome> PostCoils(MillStore* store, int n) {
  std::vector<CoilOutcome> answers;
  for (int i = 1; i <= n; ++i) {
    StatusOr<CoilOutcome> a =
        store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i, i));
    EXPECT_TRUE(a.ok()) << a.status().ToString();
    if (!a.ok()) break;
    EXPECT_EQ(a->outcome, WriteOutcome::kCreated);
    answers.push_back(*a);
  }
  return answers;
}

TEST(StoreCoilAnswerTest, RepeatGetsTheFirstAnswerCountedOnce) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  const std::vector<CoilOutcome> first = PostCoils(store.get(), 5);
  ASSERT_EQ(first.size(), 5u);
  ASSERT_EQ(first[2].added.size(), 4u);  // F6, F7 x top, bottom
  // Roll totals grow coil by coil: the third coil's total is its own.
  EXPECT_LT(first[2].added[0].predicted_wear_um,
            first[4].added[0].predicted_wear_um);
  const WearSnapshot before = Mounted(*store).Wear();

  for (int round = 0; round < 2; ++round) {
    for (int i = 0; i < 5; ++i) {
      StatusOr<CoilOutcome> again = store->AddCoil(
          MakeCoil("K" + std::to_string(i + 1), "C1", i + 1, i + 1));
      ASSERT_TRUE(again.ok()) << again.status().ToString();
      EXPECT_EQ(again->outcome, WriteOutcome::kUnchanged);
      ExpectSameAdded(*again, first[i]);
    }
  }
  EXPECT_EQ(store->Counters().coils, 5);
  EXPECT_EQ(Mounted(*store).Wear().positions[0].coils, 5);
  EXPECT_EQ(Mounted(*store).Wear().positions[0].predicted_wear_um,
            before.positions[0].predicted_wear_um);

  // Ended campaign, then a restart: still the first answer.
  ASSERT_TRUE(store->EndCampaign("C1", 9000).ok());
  StatusOr<CoilOutcome> again = store->AddCoil(MakeCoil("K3", "C1", 3, 3));
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  ExpectSameAdded(*again, first[2]);
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  for (int i = 0; i < 5; ++i) {
    again = store->AddCoil(
        MakeCoil("K" + std::to_string(i + 1), "C1", i + 1, i + 1));
    ASSERT_TRUE(again.ok()) << again.status().ToString();
    EXPECT_EQ(again->outcome, WriteOutcome::kUnchanged);
    ExpectSameAdded(*again, first[i]);
  }
  EXPECT_EQ(store->Counters().coils, 5);
  EXPECT_EQ(QueryInt(dir.File("mill.db"),
                     "SELECT COUNT(*) FROM coils WHERE wear IS NULL"),
            0);
}

TEST(StoreCoilAnswerTest, ConcurrentTwinsAllGetTheCreatedAnswer) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  ASSERT_EQ(PostCoils(store.get(), 3).size(), 3u);
  // 8 threads post the same 20 new coils; each is created once and every
  // post of it gets the same added list.
  constexpr int kThreads = 8, kCoils = 20;
  std::vector<std::vector<CoilOutcome>> answers(
      kThreads, std::vector<CoilOutcome>(kCoils));
  std::atomic<int> errors{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kCoils; ++i) {
        StatusOr<CoilOutcome> a = store->AddCoil(
            MakeCoil("T" + std::to_string(i), "C1", 100 + i, 100 + i));
        if (!a.ok()) {
          ++errors;
          continue;
        }
        answers[t][i] = *a;
      }
    });
  }
  for (auto& th : threads) th.join();
  ASSERT_EQ(errors.load(), 0);
  EXPECT_EQ(store->Counters().coils, 3 + kCoils);
  for (int i = 0; i < kCoils; ++i) {
    SCOPED_TRACE(i);
    int created = 0;
    for (int t = 0; t < kThreads; ++t) {
      created += answers[t][i].outcome == WriteOutcome::kCreated;
      ExpectSameAdded(answers[t][i], answers[0][i]);
    }
    EXPECT_EQ(created, 1);
    EXPECT_EQ(answers[0][i].added.size(), 4u);
  }
}

TEST(StoreCoilAnswerTest, AfterAPromotionARepeatStillGetsItsFirstAnswer) {
  const Dataset data = testing::SimulatedMill(11, 45, 60);
  ASSERT_FALSE(data.campaigns.empty());
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ImportDataset(data).ok());
  // Imported coils got their answers in the import's transaction.
  EXPECT_EQ(QueryInt(dir.File("mill.db"),
                     "SELECT COUNT(*) FROM coils WHERE wear IS NULL"),
            0);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1'900'000'000)).ok());
  const std::vector<CoilOutcome> first = PostCoils(store.get(), 10);
  ASSERT_EQ(first.size(), 10u);

  StatusOr<int64_t> id = store->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(engine::CalibrationRuns(&*store).Run(*id).ok());
  StatusOr<CalibrationRecord> rec = store->GetCalibration(*id);
  ASSERT_TRUE(rec.ok());
  ASSERT_TRUE(rec->promoted) << rec->message;
  // The live state is re-predicted under the new model ...
  EXPECT_NE(Mounted(*store).Wear().positions[0].predicted_wear_um,
            first.back().added[0].predicted_wear_um);
  // ... but a repeat answers what the first post was told.
  for (int i = 0; i < 10; ++i) {
    StatusOr<CoilOutcome> again = store->AddCoil(
        MakeCoil("K" + std::to_string(i + 1), "C1", i + 1, i + 1));
    ASSERT_TRUE(again.ok()) << again.status().ToString();
    ExpectSameAdded(*again, first[i]);
  }
  // A coil posted now is answered under the new model, and so is its
  // repeat; the roll total continues from the re-predicted state.
  const double total_before =
      Mounted(*store).Wear().positions[0].predicted_wear_um;
  StatusOr<CoilOutcome> k11 = store->AddCoil(MakeCoil("K11", "C1", 11, 11));
  ASSERT_TRUE(k11.ok());
  EXPECT_EQ(k11->added[0].predicted_wear_um,
            total_before + k11->added[0].wear_um);
  StatusOr<CoilOutcome> k11_again =
      store->AddCoil(MakeCoil("K11", "C1", 11, 11));
  ASSERT_TRUE(k11_again.ok());
  EXPECT_EQ(k11_again->outcome, WriteOutcome::kUnchanged);
  ExpectSameAdded(*k11_again, *k11);
  EXPECT_EQ(store->Counters().coils,
            static_cast<int64_t>(data.coil_ids.size()) + 11);
}

TEST(StoreCoilAnswerTest, VersionOneFileIsUpgradedAndItsCoilsAnswered) {
  TempDir dir;
  const std::string path = dir.File("mill.db");
  std::vector<CoilOutcome> first;
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C0", 500)).ok());
    ASSERT_TRUE(store->AddCoil(MakeCoil("OLD", "C0", 1, 9)).ok());
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
    first = PostCoils(store.get(), 6);
    ASSERT_EQ(first.size(), 6u);
  }
  {
    // Make it the version-1 file an older rollwear left: no coils.wear.
    StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)
                    ->Exec(std::string(testing::kUndoSchemaSixAndFive) +
                           "DROP INDEX coils_without_wear; "
                           "ALTER TABLE coils DROP COLUMN wear; "
                           "ALTER TABLE measurements DROP COLUMN suspect; "
                           "UPDATE schema_version SET version = 1")
                    .ok());
  }
  EXPECT_EQ(QueryInt(path, "SELECT version FROM schema_version"), 1);
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(QueryInt(path, "SELECT version FROM schema_version"),
            kSchemaVersion);
  EXPECT_EQ(QueryInt(path, "SELECT COUNT(*) FROM coils WHERE wear IS NULL"), 0);
  EXPECT_EQ(store->Counters().coils, 7);
  // Under the same (prior) model the filled-in answers are the first ones,
  // bit for bit.
  for (int i = 0; i < 6; ++i) {
    StatusOr<CoilOutcome> again = store->AddCoil(
        MakeCoil("K" + std::to_string(i + 1), "C1", i + 1, i + 1));
    ASSERT_TRUE(again.ok()) << again.status().ToString();
    EXPECT_EQ(again->outcome, WriteOutcome::kUnchanged);
    ExpectSameAdded(*again, first[i]);
  }
  StatusOr<CoilOutcome> old = store->AddCoil(MakeCoil("OLD", "C0", 1, 9));
  ASSERT_TRUE(old.ok());
  EXPECT_EQ(old->added.size(), 4u);
  EXPECT_GT(old->added[0].wear_um, 0);
  EXPECT_EQ(old->added[0].wear_um, old->added[0].predicted_wear_um);
  // New coils continue the campaign.
  StatusOr<CoilOutcome> k7 = store->AddCoil(MakeCoil("K7", "C1", 7, 7));
  ASSERT_TRUE(k7.ok());
  EXPECT_EQ(k7->outcome, WriteOutcome::kCreated);
  EXPECT_EQ(store->Counters().coils, 8);
}

}  // namespace
}  // namespace rollwear::storage
