// MillStore::AddCoilAsync, the coil path of the epoll server: every call
// gets exactly one answer; a refusal is answered on the calling thread
// before the call returns, the repeat of a committed coil through the
// executor for blocking work (its answer is read from the database), a new
// coil on the writer thread once its group is committed (so never before
// it is durable); and the answers equal those of the blocking AddCoil.
#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::ExpectWearMatchesBatch;
using testing::MakeCoil;
using testing::MakeRollChange;
using testing::OpenStore;
using testing::TempDir;

std::string CoilId(int i) { return "A" + std::to_string(100000 + i); }

// Runs blocking work at once on the calling thread, counting it.
struct InlineExecutor {
  std::atomic<int> tasks{0};
  MillStore::Executor Get() {
    return [this](std::function<void()> task) {
      ++tasks;
      task();
    };
  }
};

// Collects the answers of AddCoilAsync calls.
class Answers {
 public:
  MillStore::CoilDone Slot(int key) {
    return [this, key](StatusOr<CoilOutcome> outcome) {
      std::lock_guard<std::mutex> lock(mu_);
      ++calls_[key];
      threads_[key] = std::this_thread::get_id();
      outcomes_.insert_or_assign(key, std::move(outcome));
      cv_.notify_all();
    };
  }
  void WaitFor(size_t n) {
    std::unique_lock<std::mutex> lock(mu_);
    ASSERT_TRUE(cv_.wait_for(lock, std::chrono::seconds(30),
                             [&] { return calls_.size() >= n; }));
  }
  int Calls(int key) {
    std::lock_guard<std::mutex> lock(mu_);
    return calls_.count(key) ? calls_[key] : 0;
  }
  std::thread::id Thread(int key) {
    std::lock_guard<std::mutex> lock(mu_);
    return threads_.at(key);
  }
  StatusOr<CoilOutcome> Outcome(int key) {
    std::lock_guard<std::mutex> lock(mu_);
    return outcomes_.at(key);
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  std::map<int, int> calls_;
  std::map<int, std::thread::id> threads_;
  std::map<int, StatusOr<CoilOutcome>> outcomes_;
};

TEST(StoreAsyncCoilTest, AnswersOnceAndLikeTheBlockingCall) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  TempDir twin_dir;
  auto twin = OpenStore(twin_dir.File("mill.db"));
  ASSERT_NE(twin, nullptr);
  ASSERT_TRUE(twin->ApplyRollChange(MakeRollChange("C1", 1000)).ok());

  constexpr int kCoils = 400;
  Answers answers;
  InlineExecutor blocking;
  const int64_t commits_before = store->Counters().commits;
  for (int i = 0; i < kCoils; ++i) {
    store->AddCoilAsync(MakeCoil(CoilId(i), "C1", i + 1, i), answers.Slot(i),
                        blocking.Get());
  }
  answers.WaitFor(kCoils);
  const std::thread::id me = std::this_thread::get_id();
  for (int i = 0; i < kCoils; ++i) {
    ASSERT_EQ(answers.Calls(i), 1) << i;
    EXPECT_NE(answers.Thread(i), me) << "a new coil is answered by the writer";
    const StatusOr<CoilOutcome> got = answers.Outcome(i);
    ASSERT_TRUE(got.ok()) << got.status().ToString();
    EXPECT_EQ(got->outcome, WriteOutcome::kCreated);
    // The blocking call on a twin store gives the same answer, to the bit.
    const StatusOr<CoilOutcome> want =
        twin->AddCoil(MakeCoil(CoilId(i), "C1", i + 1, i));
    ASSERT_TRUE(want.ok());
    ASSERT_EQ(got->added.size(), want->added.size());
    for (size_t k = 0; k < want->added.size(); ++k) {
      EXPECT_EQ(got->added[k].wear_um, want->added[k].wear_um);
      EXPECT_EQ(got->added[k].predicted_wear_um,
                want->added[k].predicted_wear_um);
    }
  }
  const int64_t commits = store->Counters().commits - commits_before;
  EXPECT_LT(commits, kCoils) << "queued coils share group commits";
  EXPECT_EQ(store->Counters().coils, kCoils);
  ExpectWearMatchesBatch(*store, 1e-9);

  EXPECT_EQ(blocking.tasks.load(), 0) << "new coils need no blocking work";

  // Refusals, and repeats of committed coils through the executor (inline
  // here): answered before the call returns.
  Answers now;
  store->AddCoilAsync(MakeCoil(CoilId(7), "C1", 8, 7), now.Slot(0),
                      blocking.Get());
  EXPECT_EQ(blocking.tasks.load(), 1) << "a repeat reads the database";
  CoilIn changed = MakeCoil(CoilId(7), "C1", 8, 7);
  changed.passes[0].force_kn += 1;
  store->AddCoilAsync(changed, now.Slot(1), blocking.Get());
  CoilIn bad = MakeCoil("A-bad", "C1", 9999, 9999);
  bad.passes[0].force_kn = -1;
  store->AddCoilAsync(bad, now.Slot(2), blocking.Get());
  store->AddCoilAsync(MakeCoil("A-x", "no-such-campaign", 1, 1), now.Slot(3),
                      blocking.Get());
  EXPECT_EQ(blocking.tasks.load(), 1) << "refusals need no blocking work";
  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(now.Calls(k), 1) << k;
    EXPECT_EQ(now.Thread(k), me) << k;
  }
  ASSERT_TRUE(now.Outcome(0).ok());
  EXPECT_EQ(now.Outcome(0)->outcome, WriteOutcome::kUnchanged);
  EXPECT_EQ(now.Outcome(1).status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(now.Outcome(2).status().code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(now.Outcome(3).ok());
  EXPECT_EQ(store->Counters().coils, kCoils);
}

TEST(StoreAsyncCoilTest, QueuedCoilsAreAnsweredWhenTheStoreCloses) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  constexpr int kCoils = 300;
  std::atomic<int> ok{0}, failed{0};
  for (int i = 0; i < kCoils; ++i) {
    store->AddCoilAsync(
        MakeCoil(CoilId(i), "C1", i + 1, i),
        [&](StatusOr<CoilOutcome> outcome) { (outcome.ok() ? ok : failed)++; },
        [](std::function<void()> task) { task(); });
  }
  store.reset();  // drains the queue: every coil committed and answered
  EXPECT_EQ(ok.load() + failed.load(), kCoils);
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  // What was acknowledged is there.
  EXPECT_EQ(store->Counters().coils, ok.load());
}

}  // namespace
}  // namespace rollwear::storage
