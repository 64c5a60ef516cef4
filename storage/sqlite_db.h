// A thin RAII wrapper over the SQLite C API for the storage layer: Db (one
// connection, opened in WAL mode with synchronous=FULL, a busy timeout and
// foreign keys on), Statement (prepare / Bind* / Step / Column*), and
// Transaction (BEGIN IMMEDIATE ... COMMIT, rolled back when dropped).
//
// Every SQLite error becomes a Status: SQLITE_FULL, SQLITE_READONLY and
// SQLITE_IOERR (the database cannot be written: disk full, read-only file
// system, I/O failure) map to Unavailable; every other failure to IoError.
// Values are only ever passed through sqlite3_bind_*; SQL text is constant.
//
// Thread-safety: a Db and its Statements belong to one thread at a time
// (the caller serialises); distinct Db objects on the same file may be used
// concurrently (SQLite's WAL locking).
#ifndef ROLLWEAR_STORAGE_SQLITE_DB_H_
#define ROLLWEAR_STORAGE_SQLITE_DB_H_

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "core/base/status.h"

struct sqlite3;
struct sqlite3_stmt;

namespace rollwear::storage {

// Maps an SQLite result code (and the connection's message) to a Status;
// `what` says what was being done ("insert coil").
Status SqliteStatus(int rc, std::string_view detail, std::string_view what);

class Statement {
 public:
  Statement() = default;
  Statement(sqlite3* db, sqlite3_stmt* stmt) : db_(db), stmt_(stmt) {}
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement();

  // Parameters are 1-based. A binding error is kept and returned by the
  // next Step()/Run().
  Statement& BindInt(int i, int64_t v);
  Statement& BindDouble(int i, double v);
  // NULL for NaN (SQLite has no NaN), the value otherwise.
  Statement& BindNullableDouble(int i, double v);
  Statement& BindText(int i, std::string_view v);
  // The bytes as a BLOB.
  Statement& BindBlob(int i, std::string_view bytes);
  Statement& BindNull(int i);

  // Advances: true when a row is available, false when done.
  StatusOr<bool> Step();
  // Steps to completion, expecting no row.
  Status Run();
  // Rewinds and clears the bindings (for reuse).
  void Reset();

  // Columns are 0-based.
  int64_t ColumnInt(int i) const;
  double ColumnDouble(int i) const;
  // NaN for NULL.
  double ColumnNullableDouble(int i) const;
  std::string ColumnText(int i) const;
  // A BLOB's bytes (empty for NULL).
  std::string ColumnBlob(int i) const;
  bool ColumnIsNull(int i) const;

 private:
  Status Check(int rc, std::string_view what);

  sqlite3* db_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
  int bind_rc_ = 0;  // first failing bind's result code
};

struct DbOptions {
  bool read_only = false;  // open without write access
  int busy_timeout_ms = 10000;
};

class Db {
 public:
  // Opens (creating unless read-only) the database file and applies the
  // pragmas: journal_mode=WAL, synchronous=FULL, busy_timeout,
  // foreign_keys=ON.
  static StatusOr<std::unique_ptr<Db>> Open(const std::string& path,
                                            const DbOptions& options = {});
  ~Db();
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;

  // Runs SQL text without parameters (may hold several statements).
  Status Exec(std::string_view sql);
  StatusOr<Statement> Prepare(std::string_view sql);
  // A statement prepared once per connection and reset for reuse; the
  // pointer stays valid as long as the Db. `sql` must be a constant.
  StatusOr<Statement*> Cached(const char* sql);

  int64_t LastInsertRowId() const;
  int Changes() const;  // rows changed by the last statement
  bool InTransaction() const;
  const std::string& path() const { return path_; }
  sqlite3* handle() { return db_; }

 private:
  Db(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  sqlite3* db_ = nullptr;
  std::string path_;
  std::unordered_map<const char*, Statement> cache_;
};

// BEGIN IMMEDIATE (the write lock is taken at once, so a busy database is
// seen here rather than at the first write); rolled back unless committed.
// BEGIN and COMMIT are prepared once per Db (Cached).
class Transaction {
 public:
  static StatusOr<Transaction> Begin(Db* db);
  Transaction(Transaction&& other) noexcept : db_(other.db_) {
    other.db_ = nullptr;
  }
  Transaction& operator=(Transaction&&) = delete;
  Transaction(const Transaction&) = delete;
  ~Transaction();

  Status Commit();
  void Rollback();

 private:
  explicit Transaction(Db* db) : db_(db) {}
  Db* db_;  // null when finished
};

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_SQLITE_DB_H_
