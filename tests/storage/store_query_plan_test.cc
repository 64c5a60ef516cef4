// The store's recent reads by their query plans: judging a new measurement
// reads the most recent campaigns (ReadStoredDataset with a first campaign
// row), and each of its four queries must reach its rows through an index
// or a row-id range, never a scan of a whole table, so its cost does not
// grow with the mill's history (EXPLAIN QUERY PLAN,
// https://sqlite.org/eqp.html). The recent read returns exactly the tail of
// the whole read, for imported campaigns and one posted coil by coil.
#include <array>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "storage/store_sql.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using internal::ReadStoredDataset;
using internal::RecentCampaignsStart;
using internal::StoredDatasetQueries;
using testing::OpenStore;
using testing::SimulatedMill;
using testing::TempDir;

// The `detail` column of each step of `sql`'s query plan.
std::vector<std::string> PlanSteps(Db* db, const std::string& sql) {
  std::vector<std::string> steps;
  StatusOr<Statement> st = db->Prepare("EXPLAIN QUERY PLAN " + sql);
  EXPECT_TRUE(st.ok()) << st.status().ToString() << "\n" << sql;
  if (!st.ok()) return steps;
  for (;;) {
    StatusOr<bool> row = st->Step();
    EXPECT_TRUE(row.ok()) << row.status().ToString();
    if (!row.ok() || !*row) break;
    steps.push_back(st->ColumnText(3));
  }
  return steps;
}

// Whether a plan reads some table or index from end to end ("SCAN t",
// "SCAN t USING INDEX i": both visit every row).
bool ScansATable(const std::vector<std::string>& steps) {
  for (const std::string& s : steps) {
    if (s.rfind("SCAN ", 0) == 0) return true;
  }
  return false;
}

std::string Joined(const std::vector<std::string>& steps) {
  std::string out;
  for (const std::string& s : steps) out += "  " + s + "\n";
  return out;
}

class StoreQueryPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = SimulatedMill(21, 12, 15);
    ASSERT_FALSE(data_.campaigns.empty());
    auto store = OpenStore(dir_.File("mill.db"));
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ImportDataset(data_).ok());
    // And a campaign posted coil by coil after the import (AddCoil).
    testing::OpenCampaignWithCoils(store.get(), "OC", 12);
    store.reset();
    StatusOr<std::unique_ptr<Db>> db = Db::Open(dir_.File("mill.db"));
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    db_ = std::move(db).value();
  }

  TempDir dir_;
  Dataset data_;
  std::unique_ptr<Db> db_;
};

TEST_F(StoreQueryPlanTest, RecentReadsReachTheirRowsThroughIndexes) {
  StatusOr<int64_t> first =
      RecentCampaignsStart(db_.get(), data_.campaigns.back().id, 4);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  ASSERT_GT(*first, 1);
  const std::array<std::string, 4> queries = StoredDatasetQueries(*first);
  for (const std::string& sql : queries) {
    const std::vector<std::string> steps = PlanSteps(db_.get(), sql);
    ASSERT_FALSE(steps.empty()) << sql;
    EXPECT_FALSE(ScansATable(steps)) << sql << "\n" << Joined(steps);
  }
  // The check sees a scan where there is one: the whole read scans passes
  // (every row is wanted; the row-order scan costs less than the index walk).
  const std::vector<std::string> whole =
      PlanSteps(db_.get(), StoredDatasetQueries(0)[2]);
  EXPECT_TRUE(ScansATable(whole)) << Joined(whole);
}

// The replay of one campaign runs per GET /v1/rolls/{id} mount, per
// measurement under a model with per-roll factors (their re-estimate,
// store_roll_factors.cc) and when a model is installed: it reaches the
// campaign's coils and passes through their indexes, never a scan.
TEST_F(StoreQueryPlanTest, ReplayOfOneCampaignReachesItsRowsThroughIndexes) {
  const std::vector<std::string> steps =
      PlanSteps(db_.get(), internal::ReplayCampaignQuery());
  ASSERT_FALSE(steps.empty());
  EXPECT_FALSE(ScansATable(steps)) << Joined(steps);
  // Both tables are searched (a plan that dropped the join would pass the
  // check above vacuously).
  bool coils = false, passes = false;
  for (const std::string& s : steps) {
    coils = coils || s.rfind("SEARCH c ", 0) == 0;
    passes = passes || s.rfind("SEARCH p ", 0) == 0;
  }
  EXPECT_TRUE(coils && passes) << Joined(steps);
}

TEST_F(StoreQueryPlanTest, RecentReadIsTheTailOfTheWholeRead) {
  constexpr int kRecent = 5;
  StatusOr<int64_t> first = RecentCampaignsStart(db_.get(), "OC", kRecent);
  ASSERT_TRUE(first.ok());
  StatusOr<Dataset> whole = ReadStoredDataset(db_.get());
  StatusOr<Dataset> recent = ReadStoredDataset(db_.get(), nullptr, *first);
  ASSERT_TRUE(whole.ok() && recent.ok());
  ASSERT_EQ(recent->campaigns.size(), static_cast<size_t>(kRecent));
  const int offset = static_cast<int>(whole->campaigns.size()) - kRecent;
  std::vector<const Pass*> tail;
  for (const Pass& p : whole->passes) {
    if (p.campaign >= offset) tail.push_back(&p);
  }
  ASSERT_EQ(recent->passes.size(), tail.size());
  ASSERT_GT(tail.size(), 0u);
  for (size_t i = 0; i < tail.size(); ++i) {
    const Pass& a = *tail[i];
    const Pass& b = recent->passes[i];
    ASSERT_EQ(whole->coil_ids[a.coil], recent->coil_ids[b.coil]) << i;
    EXPECT_EQ(a.campaign - offset, b.campaign);
    EXPECT_EQ(a.stand, b.stand);
    EXPECT_EQ(a.seq, b.seq);
    EXPECT_EQ(a.rolled_at, b.rolled_at);
    EXPECT_EQ(a.force_kn, b.force_kn);
    EXPECT_EQ(whole->grades[a.grade], recent->grades[b.grade]);
  }
  size_t tail_measurements = 0;
  for (const Measurement& m : whole->measurements) {
    if (m.campaign >= offset) ++tail_measurements;
  }
  EXPECT_EQ(recent->measurements.size(), tail_measurements);
  EXPECT_EQ(recent->mounts.size(), static_cast<size_t>(kRecent) *
                                       whole->mounts.size() /
                                       whole->campaigns.size());
}

}  // namespace
}  // namespace rollwear::storage
