// Group commit under concurrency: 16 threads post 2000 coils with
// duplicates and conflicting repeats mixed in; each coil counts once, the
// live wear equals the batch prediction, and fewer transactions than coils
// were committed. A transaction that fails (an injected trigger) fails
// every caller of its batch and leaves nothing of it behind.
#include <atomic>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::ExpectWearMatchesBatch;
using testing::MakeCoil;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

constexpr int kThreads = 16;
constexpr int kCoils = 2000;

std::string CoilId(int i) { return "K" + std::to_string(100000 + i); }

TEST(StoreConcurrencyTest, SixteenThreadsTwoThousandCoilsWithDuplicates) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  const int64_t commits_before = store->Counters().commits;

  std::atomic<int> created{0}, unchanged{0}, conflicts{0}, errors{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      std::mt19937 rng(1234 + t);
      for (int i = t; i < kCoils; i += kThreads) {
        const CoilIn coil = MakeCoil(CoilId(i), "C1", i + 1, i);
        StatusOr<CoilOutcome> r = store->AddCoil(coil);
        if (!r.ok()) {
          ++errors;
          continue;
        }
        (r->outcome == WriteOutcome::kCreated ? created : unchanged)++;
        // A duplicate of some coil, possibly not posted yet by its thread
        // (then this one creates it and the owner sees kUnchanged).
        if (rng() % 4 == 0) {
          const int j = static_cast<int>(rng() % kCoils);
          StatusOr<CoilOutcome> d =
              store->AddCoil(MakeCoil(CoilId(j), "C1", j + 1, j));
          if (!d.ok()) {
            ++errors;
          } else {
            (d->outcome == WriteOutcome::kCreated ? created : unchanged)++;
          }
        }
        // The own coil again with other content: a conflict.
        if (rng() % 8 == 0) {
          CoilIn changed = coil;
          changed.passes[0].force_kn += 1;
          StatusOr<CoilOutcome> c = store->AddCoil(changed);
          if (c.status().code() == StatusCode::kAlreadyExists) {
            ++conflicts;
          } else {
            ++errors;
          }
        }
      }
    });
  }
  for (std::thread& t : threads) t.join();

  EXPECT_EQ(errors.load(), 0);
  EXPECT_EQ(created.load(), kCoils);  // each coil created exactly once
  EXPECT_GT(unchanged.load(), 0);
  EXPECT_GT(conflicts.load(), 0);
  const StoreCounters n = store->Counters();
  EXPECT_EQ(n.coils, kCoils);
  const int64_t commits = n.commits - commits_before;
  EXPECT_LT(commits, kCoils) << "no group commit happened";
  EXPECT_GT(commits, 0);
  std::cout << "[ info ] " << kCoils << " coils in " << commits
            << " group commits\n";
  const WearSnapshot snap = Mounted(*store).Wear();
  ASSERT_EQ(snap.positions.size(), 4u);
  for (const PositionWear& w : snap.positions) EXPECT_EQ(w.coils, kCoils);
  ExpectWearMatchesBatch(*store, 1e-9);

  // The same after a restart, to the bit.
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const WearSnapshot again = Mounted(*store).Wear();
  ASSERT_EQ(again.positions.size(), snap.positions.size());
  for (size_t i = 0; i < snap.positions.size(); ++i) {
    EXPECT_EQ(again.positions[i].predicted_wear_um,
              snap.positions[i].predicted_wear_um);
  }
  EXPECT_EQ(store->Counters().coils, kCoils);
}

TEST(StoreConcurrencyTest, FailedCommitFailsItsBatchAndAppliesNothingOfIt) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  {
    // Another connection poisons inserts of coils named BAD*.
    StatusOr<std::unique_ptr<Db>> db = Db::Open(dir.File("mill.db"));
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)
                    ->Exec("CREATE TRIGGER poison BEFORE INSERT ON coils "
                           "WHEN NEW.coil_id LIKE 'BAD%' BEGIN "
                           "SELECT RAISE(ABORT, 'injected failure'); END")
                    .ok());
  }
  constexpr int kPerThread = 60;
  std::vector<std::vector<int>> ok_coils(8), failed_coils(8);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < kPerThread; ++k) {
        const int i = t * kPerThread + k;
        const bool bad = i % 37 == 5;
        CoilIn coil =
            MakeCoil((bad ? "BAD" : "G") + std::to_string(i), "C1", i + 1, i);
        StatusOr<CoilOutcome> r = store->AddCoil(coil);
        if (r.ok()) {
          EXPECT_FALSE(bad);
          ok_coils[t].push_back(i);
        } else {
          EXPECT_EQ(r.status().code(), StatusCode::kIoError)
              << r.status().ToString();
          failed_coils[t].push_back(i);
        }
      }
    });
  }
  for (std::thread& t : threads) t.join();

  std::set<std::string> acknowledged, rejected;
  for (int t = 0; t < 8; ++t) {
    for (int i : ok_coils[t]) acknowledged.insert(std::to_string(i));
    for (int i : failed_coils[t]) rejected.insert(std::to_string(i));
  }
  EXPECT_GT(rejected.size(), 0u);
  StatusOr<Dataset> data = store->ExportDataset();
  ASSERT_TRUE(data.ok());
  std::set<std::string> stored;
  for (const std::string& id : data->coil_ids) {
    stored.insert(id.substr(id[0] == 'B' ? 3 : 1));
  }
  EXPECT_EQ(stored, acknowledged);  // nothing acknowledged is lost,
  for (const std::string& id : rejected) {
    EXPECT_EQ(stored.count(id), 0u) << id;  // nothing rejected is stored
  }
  EXPECT_EQ(store->Counters().coils, static_cast<int64_t>(acknowledged.size()));
  ExpectWearMatchesBatch(*store);

  // Remove the poison: every rejected good coil can now be posted (its
  // pending state was rolled back, so it is not a duplicate of itself).
  {
    StatusOr<std::unique_ptr<Db>> db = Db::Open(dir.File("mill.db"));
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)->Exec("DROP TRIGGER poison").ok());
  }
  for (const std::string& id : rejected) {
    const int i = std::stoi(id);
    const bool bad = i % 37 == 5;
    StatusOr<CoilOutcome> r =
        store->AddCoil(MakeCoil((bad ? "BAD" : "G") + id, "C1", i + 1, i));
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_EQ(r->outcome, WriteOutcome::kCreated);
  }
  EXPECT_EQ(store->Counters().coils, 8 * kPerThread);
  ExpectWearMatchesBatch(*store);
}

}  // namespace
}  // namespace rollwear::storage
