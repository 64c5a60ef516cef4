// The store's queries that run per request or per measurement, by their
// query plans: each must reach its rows through an index or a row-id
// range, never a scan of a whole table, so its cost does not grow with the
// mill's history (EXPLAIN QUERY PLAN, https://sqlite.org/eqp.html). (A new
// measurement's judge runs no query: store_judge_test.cc.)
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

}  // namespace
}  // namespace rollwear::storage
