// The SQLite wrapper (pragmas, error mapping, transactions) and the schema
// migrations: creating, upgrading, refusing newer and foreign files.
#include "storage/schema.h"

#include <gtest/gtest.h>

#include "engine/wear_prediction.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

std::unique_ptr<Db> MustOpen(const std::string& path, DbOptions o = {}) {
  StatusOr<std::unique_ptr<Db>> db = Db::Open(path, o);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  return db.ok() ? std::move(db).value() : nullptr;
}

int64_t QueryInt(Db* db, const char* sql) {
  StatusOr<Statement> st = db->Prepare(sql);
  EXPECT_TRUE(st.ok()) << st.status().ToString();
  StatusOr<bool> row = st->Step();
  EXPECT_TRUE(row.ok() && *row) << sql;
  return st->ColumnInt(0);
}

std::string QueryText(Db* db, const char* sql) {
  StatusOr<Statement> st = db->Prepare(sql);
  EXPECT_TRUE(st.ok()) << st.status().ToString();
  StatusOr<bool> row = st->Step();
  EXPECT_TRUE(row.ok() && *row) << sql;
  return st->ColumnText(0);
}

TEST(StoreSqliteTest, PragmasAreSetOnOpen) {
  TempDir dir;
  auto db = MustOpen(dir.File("p.db"));
  EXPECT_EQ(QueryText(db.get(), "PRAGMA journal_mode"), "wal");
  EXPECT_EQ(QueryInt(db.get(), "PRAGMA synchronous"), 2);  // FULL
  EXPECT_EQ(QueryInt(db.get(), "PRAGMA foreign_keys"), 1);
  EXPECT_GT(QueryInt(db.get(), "PRAGMA busy_timeout"), 0);
}

TEST(StoreSqliteTest, BindStepColumnAndTransactionRollback) {
  TempDir dir;
  auto db = MustOpen(dir.File("t.db"));
  ASSERT_TRUE(db->Exec("CREATE TABLE t (a INTEGER, b REAL, c TEXT)").ok());
  {
    StatusOr<Transaction> txn = Transaction::Begin(db.get());
    ASSERT_TRUE(txn.ok());
    StatusOr<Statement> st = db->Prepare("INSERT INTO t VALUES (?, ?, ?)");
    ASSERT_TRUE(st.ok());
    st->BindInt(1, 7).BindDouble(2, 0.1).BindText(3, "x'); DROP TABLE t; --");
    ASSERT_TRUE(st->Run().ok());
    // Dropped without Commit: rolled back.
  }
  EXPECT_EQ(QueryInt(db.get(), "SELECT COUNT(*) FROM t"), 0);
  {
    StatusOr<Transaction> txn = Transaction::Begin(db.get());
    ASSERT_TRUE(txn.ok());
    StatusOr<Statement*> st = db->Cached("INSERT INTO t VALUES (?, ?, ?)");
    ASSERT_TRUE(st.ok());
    (*st)->BindInt(1, 7).BindDouble(2, 0.1).BindText(3, "x'); DROP TABLE t;");
    ASSERT_TRUE((*st)->Run().ok());
    ASSERT_TRUE(txn->Commit().ok());
  }
  StatusOr<Statement> st = db->Prepare("SELECT a, b, c FROM t");
  ASSERT_TRUE(st.ok());
  StatusOr<bool> row = st->Step();
  ASSERT_TRUE(row.ok() && *row);
  EXPECT_EQ(st->ColumnInt(0), 7);
  EXPECT_EQ(st->ColumnDouble(1), 0.1);
  EXPECT_EQ(st->ColumnText(2), "x'); DROP TABLE t;");  // stored as a value
}

TEST(StoreSqliteTest, DatabaseFullIsUnavailable) {
  TempDir dir;
  auto db = MustOpen(dir.File("full.db"));
  ASSERT_TRUE(db->Exec("CREATE TABLE t (x TEXT)").ok());
  ASSERT_TRUE(db->Exec("PRAGMA max_page_count = 8").ok());
  Status s;
  for (int i = 0; i < 100 && s.ok(); ++i) {
    StatusOr<Statement> st = db->Prepare("INSERT INTO t VALUES (?)");
    ASSERT_TRUE(st.ok());
    st->BindText(1, std::string(4000, 'x'));
    s = st->Run();
  }
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.code(), StatusCode::kUnavailable) << s.ToString();
  EXPECT_NE(s.message().find("database not writable"), std::string::npos);
  EXPECT_NE(s.message().find("full"), std::string::npos);
}

TEST(StoreSqliteTest, ReadOnlyIsUnavailableOtherErrorsAreIoError) {
  TempDir dir;
  {
    auto db = MustOpen(dir.File("ro.db"));
    ASSERT_TRUE(db->Exec("CREATE TABLE t (x INTEGER)").ok());
  }
  DbOptions o;
  o.read_only = true;
  auto ro = MustOpen(dir.File("ro.db"), o);
  Status s = ro->Exec("INSERT INTO t VALUES (1)");
  EXPECT_EQ(s.code(), StatusCode::kUnavailable) << s.ToString();
  EXPECT_NE(s.message().find("read-only"), std::string::npos);
  s = ro->Exec("SELECT * FROM no_such_table");
  EXPECT_EQ(s.code(), StatusCode::kIoError) << s.ToString();
}

TEST(SchemaTest, NewFileGetsTheCurrentVersion) {
  TempDir dir;
  auto db = MustOpen(dir.File("new.db"));
  StatusOr<int> v = ReadSchemaVersion(db.get());
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(*v, 0);
  ASSERT_TRUE(MigrateSchema(db.get()).ok());
  v = ReadSchemaVersion(db.get());
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(*v, kSchemaVersion);
  for (const char* table : {"campaigns", "mounts", "coils", "passes",
                            "measurements", "models", "calibrations"}) {
    StatusOr<Statement> st = db->Prepare(
        "SELECT COUNT(*) FROM sqlite_schema WHERE type='table' AND name=?");
    ASSERT_TRUE(st.ok());
    st->BindText(1, table);
    ASSERT_TRUE(st->Step().ok());
    EXPECT_EQ(st->ColumnInt(0), 1) << table;
  }
  // Migrating again is a no-op.
  ASSERT_TRUE(MigrateSchema(db.get()).ok());
  EXPECT_EQ(QueryInt(db.get(), "SELECT COUNT(*) FROM schema_version"), 1);
}

// Version 3 drops the index of passes by campaign; a version-2 file (which
// has it) loses it on open, and its campaigns' passes still replay: the
// open campaign's wear after reopening equals the wear before.
TEST(SchemaTest, VersionTwoFileLosesThePassesByCampaignIndex) {
  TempDir dir;
  const std::string path = dir.File("v2.db");
  WearSnapshot before;
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
    for (int i = 1; i <= 20; ++i) {
      ASSERT_TRUE(
          store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i, i)).ok());
    }
    before = Mounted(*store).Wear();
  }
  {
    auto db = MustOpen(path);
    // Versions 6, 5, 4 and 3 undone.
    ASSERT_TRUE(db->Exec(std::string(testing::kUndoSchemaSixAndFive) +
                         "CREATE INDEX passes_by_campaign ON passes "
                         "(campaign); ALTER TABLE measurements DROP COLUMN "
                         "suspect; UPDATE schema_version SET version = 2")
                    .ok());
  }
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  const WearSnapshot after = Mounted(*store).Wear();
  ASSERT_EQ(after.positions.size(), before.positions.size());
  ASSERT_FALSE(after.positions.empty());
  for (size_t i = 0; i < after.positions.size(); ++i) {
    EXPECT_EQ(after.positions[i].coils, 20);
    EXPECT_NEAR(after.positions[i].predicted_wear_um,
                before.positions[i].predicted_wear_um,
                1e-9 * before.positions[i].predicted_wear_um);
  }
  store.reset();
  auto db = MustOpen(path);
  EXPECT_EQ(QueryInt(db.get(), "SELECT version FROM schema_version"),
            kSchemaVersion);
  EXPECT_EQ(QueryInt(db.get(),
                     "SELECT COUNT(*) FROM sqlite_schema WHERE "
                     "name = 'passes_by_campaign'"),
            0);
}

TEST(SchemaTest, EmptyVersionZeroFileIsUpgradedOnOpen) {
  TempDir dir;
  {
    // A version-0 file made by hand: schema_version present, nothing else.
    auto db = MustOpen(dir.File("v0.db"));
    ASSERT_TRUE(db->Exec("CREATE TABLE schema_version (version INTEGER NOT "
                         "NULL) STRICT; INSERT INTO schema_version VALUES (0)")
                    .ok());
  }
  auto store = OpenStore(dir.File("v0.db"));
  ASSERT_NE(store, nullptr);
  EXPECT_TRUE(store->Healthy());
  store.reset();
  auto db = MustOpen(dir.File("v0.db"));
  EXPECT_EQ(QueryInt(db.get(), "SELECT version FROM schema_version"),
            kSchemaVersion);
  EXPECT_EQ(QueryInt(db.get(), "SELECT COUNT(*) FROM schema_version"), 1);
}

TEST(SchemaTest, NewerFileIsRefusedAndLeftUntouched) {
  TempDir dir;
  {
    auto store = OpenStore(dir.File("newer.db"));
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(
        store->ApplyRollChange(testing::MakeRollChange("C1", 1000)).ok());
  }
  {
    auto db = MustOpen(dir.File("newer.db"));
    ASSERT_TRUE(db->Exec("UPDATE schema_version SET version = " +
                         std::to_string(kSchemaVersion + 1))
                    .ok());
  }
  StatusOr<std::unique_ptr<MillStore>> store =
      engine::OpenStore(dir.File("newer.db"));
  ASSERT_FALSE(store.ok());
  EXPECT_EQ(store.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(store.status().message(),
            "database schema version " + std::to_string(kSchemaVersion + 1) +
                " is newer than this rollwear (supports up to " +
                std::to_string(kSchemaVersion) + "); upgrade rollwear");
  auto db = MustOpen(dir.File("newer.db"));
  EXPECT_EQ(QueryInt(db.get(), "SELECT version FROM schema_version"),
            kSchemaVersion + 1);
  EXPECT_EQ(QueryInt(db.get(), "SELECT COUNT(*) FROM campaigns"), 1);
}

TEST(SchemaTest, OlderFileIsUpgradedByTheNextMigrationKeepingData) {
  TempDir dir;
  const int next_version = kSchemaVersion + 1;
  {
    auto store = OpenStore(dir.File("v1.db"));
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(
        store->ApplyRollChange(testing::MakeRollChange("C1", 1000)).ok());
    ASSERT_TRUE(store->AddCoil(testing::MakeCoil("K1", "C1", 1)).ok());
  }
  // A build with one more migration opens the current file.
  std::vector<Migration> next = SchemaMigrations();
  next.push_back({next_version, "campaign notes",
                  "ALTER TABLE campaigns ADD COLUMN note TEXT; "
                  "UPDATE campaigns SET note = 'migrated';"});
  auto db = MustOpen(dir.File("v1.db"));
  ASSERT_TRUE(MigrateSchema(db.get(), next).ok());
  EXPECT_EQ(QueryInt(db.get(), "SELECT version FROM schema_version"),
            next_version);
  EXPECT_EQ(QueryText(db.get(), "SELECT note FROM campaigns"), "migrated");
  EXPECT_EQ(QueryInt(db.get(), "SELECT COUNT(*) FROM passes"), 2);
  // And this build (which supports only kSchemaVersion) now refuses it.
  db.reset();
  StatusOr<std::unique_ptr<MillStore>> store =
      engine::OpenStore(dir.File("v1.db"));
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find(
                "schema version " + std::to_string(next_version) + " is newer"),
            std::string::npos);
}

TEST(SchemaTest, FailingMigrationLeavesTheFileAsItWas) {
  TempDir dir;
  {
    auto store = OpenStore(dir.File("v1.db"));
    ASSERT_NE(store, nullptr);
  }
  std::vector<Migration> next = SchemaMigrations();
  next.push_back({kSchemaVersion + 1, "half done",
                  "CREATE TABLE extra_table (x INTEGER); "
                  "ALTER TABLE no_such_table ADD COLUMN y TEXT;"});
  auto db = MustOpen(dir.File("v1.db"));
  Status s = MigrateSchema(db.get(), next);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("migration to version " +
                             std::to_string(kSchemaVersion + 1)),
            std::string::npos);
  EXPECT_EQ(QueryInt(db.get(), "SELECT version FROM schema_version"),
            kSchemaVersion);
  EXPECT_EQ(QueryInt(db.get(),
                     "SELECT COUNT(*) FROM sqlite_schema WHERE "
                     "name = 'extra_table'"),
            0);
}

TEST(SchemaTest, ForeignDatabaseIsRefused) {
  TempDir dir;
  {
    auto db = MustOpen(dir.File("other.db"));
    ASSERT_TRUE(db->Exec("CREATE TABLE something (x INTEGER)").ok());
  }
  StatusOr<std::unique_ptr<MillStore>> store =
      engine::OpenStore(dir.File("other.db"));
  ASSERT_FALSE(store.ok());
  EXPECT_EQ(store.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(store.status().message().find("not a rollwear database"),
            std::string::npos);
}

}  // namespace
}  // namespace rollwear::storage
