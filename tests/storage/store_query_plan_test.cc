// The store's queries that run per request or per measurement, by their
// query plans: each must reach its rows through an index or a row-id
// range, never a scan of a whole table, so its cost does not grow with the
// mill's history (EXPLAIN QUERY PLAN, https://sqlite.org/eqp.html). (A new
// measurement's judge runs no query: store_judge_test.cc.)
#include <algorithm>
#include <array>
#include <map>
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
// "SCAN t USING INDEX i": both visit every row), other than the tables
// (by alias) in `may_scan`.
bool ScansATable(const std::vector<std::string>& steps,
                 const std::vector<std::string>& may_scan = {}) {
  for (const std::string& s : steps) {
    if (s.rfind("SCAN ", 0) != 0) continue;
    const std::string table = s.substr(5, s.find(' ', 5) - 5);
    if (std::find(may_scan.begin(), may_scan.end(), table) == may_scan.end()) {
      return true;
    }
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
    // The inventory of the live store (its catalog summed as the import
    // and the coils committed), before it is reopened.
    StatusOr<std::vector<RollSummary>> live = store->RollInventory();
    ASSERT_TRUE(live.ok()) << live.status().ToString();
    live_inventory_ = std::move(live).value();
    store.reset();
    StatusOr<std::unique_ptr<Db>> db = Db::Open(dir_.File("mill.db"));
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    db_ = std::move(db).value();
  }

  TempDir dir_;
  Dataset data_;
  std::unique_ptr<Db> db_;
  std::vector<RollSummary> live_inventory_;
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

// Every query of a per-request or per-measurement path (store_sql.h's
// PerRequestQueries: a coil's admission and repeat, a measurement's and a
// profile's campaign, a stored profile, the dashboard's profiles, the
// replay, which the dashboard's wear history runs too) reaches passes, coils
// and measurements through an index. The list is the one the store's functions
// run (the same constants), so a query changed there is checked here.
TEST_F(StoreQueryPlanTest, NoPerRequestQueryScansPassesCoilsOrMeasurements) {
  const std::vector<internal::PerRequestQuery> queries =
      internal::PerRequestQueries();
  ASSERT_GE(queries.size(), 7u);
  for (const internal::PerRequestQuery& q : queries) {
    const std::vector<std::string> steps = PlanSteps(db_.get(), q.sql);
    ASSERT_FALSE(steps.empty()) << q.name;
    EXPECT_FALSE(ScansATable(steps, q.may_scan)) << q.name << "\n"
                                                 << Joined(steps);
  }
}

// The check above fails on a scan: a query by a column without an index
// (passes by force) is planned as one.
TEST_F(StoreQueryPlanTest, TheCheckSeesAScan) {
  const std::vector<std::string> steps =
      PlanSteps(db_.get(), "SELECT p.coil FROM passes p WHERE p.force_kn > ?");
  EXPECT_TRUE(ScansATable(steps)) << Joined(steps);
  EXPECT_FALSE(ScansATable(steps, {"p"})) << Joined(steps);
}

// GET /v1/rolls adds each roll's rolled length from the catalog: equal to
// the sum over the stored passes of its stands in its campaigns, both in
// the store that imported and posted them (the catalog summed as they
// committed) and in the store reopened on the file (summed from the
// passes).
TEST_F(StoreQueryPlanTest, InventoryLengthsAreTheStoredPasses) {
  StatusOr<Statement> st = db_->Prepare(
      "SELECT m.roll_id, SUM(p.length_m) FROM mounts m "
      "JOIN coils c ON c.campaign = m.campaign "
      "JOIN passes p ON p.coil = c.id AND p.stand = m.stand "
      "GROUP BY m.roll_id");
  ASSERT_TRUE(st.ok()) << st.status().ToString();
  std::map<std::string, double> expected;
  for (;;) {
    StatusOr<bool> row = st->Step();
    ASSERT_TRUE(row.ok());
    if (!*row) break;
    expected[st->ColumnText(0)] = st->ColumnDouble(1);
  }
  db_.reset();
  auto store = testing::OpenStore(dir_.File("mill.db"));
  ASSERT_NE(store, nullptr);
  StatusOr<std::vector<RollSummary>> reopened = store->RollInventory();
  ASSERT_TRUE(reopened.ok()) << reopened.status().ToString();
  for (const std::vector<RollSummary>* rolls :
       {&live_inventory_, &reopened.value()}) {
    ASSERT_EQ(rolls->size(), expected.size());
    for (const RollSummary& r : *rolls) {
      ASSERT_EQ(expected.count(r.roll_id), 1u) << r.roll_id;
      EXPECT_GT(r.total_rolled_m, 0) << r.roll_id;
      EXPECT_NEAR(r.total_rolled_m, expected[r.roll_id],
                  1e-9 * expected[r.roll_id])
          << r.roll_id;
    }
  }
}

}  // namespace
}  // namespace rollwear::storage
