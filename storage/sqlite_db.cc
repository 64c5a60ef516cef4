#include "storage/sqlite_db.h"

#include <cmath>
#include <limits>
#include <utility>

#include <sqlite3.h>

namespace rollwear::storage {

Status SqliteStatus(int rc, std::string_view detail, std::string_view what) {
  std::string where(what);
  where += ": ";
  where.append(detail);
  switch (rc & 0xff) {
    case SQLITE_OK:
    case SQLITE_ROW:
    case SQLITE_DONE:
      return Status::Ok();
    case SQLITE_FULL:
      return Status::Unavailable(
          "database not writable: the disk or database is full (" + where +
          ")");
    case SQLITE_READONLY:
      return Status::Unavailable(
          "database not writable: the file or file system is read-only (" +
          where + ")");
    case SQLITE_IOERR:
      return Status::Unavailable("database not writable: I/O error (" + where +
                                 ")");
    default:
      return Status::IoError("database error (" + where + ")");
  }
}

// ---------------------------------------------------------------- Statement

Statement::Statement(Statement&& other) noexcept
    : db_(other.db_), stmt_(other.stmt_), bind_rc_(other.bind_rc_) {
  other.stmt_ = nullptr;
}

Statement& Statement::operator=(Statement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(stmt_);
    db_ = other.db_;
    stmt_ = other.stmt_;
    bind_rc_ = other.bind_rc_;
    other.stmt_ = nullptr;
  }
  return *this;
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::BindInt(int i, int64_t v) {
  const int rc = sqlite3_bind_int64(stmt_, i, v);
  if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) bind_rc_ = rc;
  return *this;
}

Statement& Statement::BindDouble(int i, double v) {
  const int rc = sqlite3_bind_double(stmt_, i, v);
  if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) bind_rc_ = rc;
  return *this;
}

Statement& Statement::BindNullableDouble(int i, double v) {
  return std::isnan(v) ? BindNull(i) : BindDouble(i, v);
}

Statement& Statement::BindText(int i, std::string_view v) {
  const int rc = sqlite3_bind_text(
      stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) bind_rc_ = rc;
  return *this;
}

Statement& Statement::BindBlob(int i, std::string_view bytes) {
  const int rc = sqlite3_bind_blob(
      stmt_, i, bytes.data(), static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) bind_rc_ = rc;
  return *this;
}

Statement& Statement::BindNull(int i) {
  const int rc = sqlite3_bind_null(stmt_, i);
  if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) bind_rc_ = rc;
  return *this;
}

Status Statement::Check(int rc, std::string_view what) {
  return SqliteStatus(rc, sqlite3_errmsg(db_), what);
}

StatusOr<bool> Statement::Step() {
  if (bind_rc_ != SQLITE_OK) {
    const int rc = bind_rc_;
    bind_rc_ = SQLITE_OK;
    return SqliteStatus(rc, sqlite3_errstr(rc), sqlite3_sql(stmt_));
  }
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  Status s = Check(rc, sqlite3_sql(stmt_));
  sqlite3_reset(stmt_);
  return s;
}

Status Statement::Run() {
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, Step());
  if (row) {
    return Status::Internal(std::string("statement returned a row: ") +
                            sqlite3_sql(stmt_));
  }
  return Status::Ok();
}

void Statement::Reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
  bind_rc_ = SQLITE_OK;
}

int64_t Statement::ColumnInt(int i) const {
  return sqlite3_column_int64(stmt_, i);
}

double Statement::ColumnDouble(int i) const {
  return sqlite3_column_double(stmt_, i);
}

double Statement::ColumnNullableDouble(int i) const {
  if (ColumnIsNull(i)) return std::numeric_limits<double>::quiet_NaN();
  return sqlite3_column_double(stmt_, i);
}

std::string Statement::ColumnText(int i) const {
  const unsigned char* text = sqlite3_column_text(stmt_, i);
  const int n = sqlite3_column_bytes(stmt_, i);
  if (text == nullptr) return std::string();
  return std::string(reinterpret_cast<const char*>(text),
                     static_cast<size_t>(n));
}

std::string Statement::ColumnBlob(int i) const {
  const void* blob = sqlite3_column_blob(stmt_, i);
  const int n = sqlite3_column_bytes(stmt_, i);
  if (blob == nullptr) return std::string();
  return std::string(static_cast<const char*>(blob), static_cast<size_t>(n));
}

bool Statement::ColumnIsNull(int i) const {
  return sqlite3_column_type(stmt_, i) == SQLITE_NULL;
}

// ----------------------------------------------------------------------- Db

StatusOr<std::unique_ptr<Db>> Db::Open(const std::string& path,
                                       const DbOptions& options) {
  sqlite3* handle = nullptr;
  const int flags =
      (options.read_only ? SQLITE_OPEN_READONLY
                         : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) |
      SQLITE_OPEN_NOMUTEX;
  const int rc = sqlite3_open_v2(path.c_str(), &handle, flags, nullptr);
  if (rc != SQLITE_OK) {
    Status s = SqliteStatus(
        rc, handle != nullptr ? sqlite3_errmsg(handle) : sqlite3_errstr(rc),
        "open " + path);
    sqlite3_close(handle);
    if (s.ok()) s = Status::IoError("cannot open database " + path);
    return s;
  }
  sqlite3_extended_result_codes(handle, 1);
  std::unique_ptr<Db> db(new Db(handle, path));
  ROLLWEAR_RETURN_IF_ERROR(db->Exec("PRAGMA busy_timeout = " +
                                    std::to_string(options.busy_timeout_ms)));
  if (!options.read_only) {
    // journal_mode answers with a row naming the mode in force.
    ROLLWEAR_ASSIGN_OR_RETURN(Statement wal,
                              db->Prepare("PRAGMA journal_mode = WAL"));
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, wal.Step());
    if (!row || wal.ColumnText(0) != "wal") {
      return Status::IoError("database " + path +
                             ": cannot switch to WAL journal mode");
    }
  }
  ROLLWEAR_RETURN_IF_ERROR(db->Exec("PRAGMA synchronous = FULL"));
  ROLLWEAR_RETURN_IF_ERROR(db->Exec("PRAGMA foreign_keys = ON"));
  return db;
}

Db::~Db() {
  cache_.clear();  // statements must be finalised before the connection
  sqlite3_close_v2(db_);
}

Status Db::Exec(std::string_view sql) {
  const std::string text(sql);
  char* err = nullptr;
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &err);
  if (rc == SQLITE_OK) return Status::Ok();
  Status s = SqliteStatus(rc, err != nullptr ? err : sqlite3_errmsg(db_),
                          text.substr(0, 80));
  sqlite3_free(err);
  return s;
}

StatusOr<Statement> Db::Prepare(std::string_view sql) {
  sqlite3_stmt* stmt = nullptr;
  const int rc = sqlite3_prepare_v2(
      db_, sql.data(), static_cast<int>(sql.size()), &stmt, nullptr);
  if (rc != SQLITE_OK) {
    return SqliteStatus(rc, sqlite3_errmsg(db_),
                        "prepare " + std::string(sql.substr(0, 80)));
  }
  return Statement(db_, stmt);
}

StatusOr<Statement*> Db::Cached(const char* sql) {
  auto it = cache_.find(sql);
  if (it == cache_.end()) {
    ROLLWEAR_ASSIGN_OR_RETURN(Statement s, Prepare(sql));
    it = cache_.emplace(sql, std::move(s)).first;
  } else {
    it->second.Reset();
  }
  return &it->second;
}

int64_t Db::LastInsertRowId() const { return sqlite3_last_insert_rowid(db_); }
int Db::Changes() const { return sqlite3_changes(db_); }
bool Db::InTransaction() const { return sqlite3_get_autocommit(db_) == 0; }

// -------------------------------------------------------------- Transaction

namespace {

// BEGIN and COMMIT run once per group commit: prepared once per connection
// (Db::Cached, keyed by these arrays' addresses) instead of being parsed
// again by sqlite3_exec each time.
constexpr char kBeginImmediate[] = "BEGIN IMMEDIATE";
constexpr char kCommit[] = "COMMIT";

Status RunCached(Db* db, const char* sql) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement* const st, db->Cached(sql));
  Status s = st->Run();
  st->Reset();
  return s;
}

}  // namespace

StatusOr<Transaction> Transaction::Begin(Db* db) {
  ROLLWEAR_RETURN_IF_ERROR(RunCached(db, kBeginImmediate));
  return Transaction(db);
}

Transaction::~Transaction() { Rollback(); }

Status Transaction::Commit() {
  if (db_ == nullptr) return Status::Internal("transaction already finished");
  Status s = RunCached(db_, kCommit);
  if (!s.ok()) {
    // A failed COMMIT may leave the transaction open (e.g. SQLITE_BUSY);
    // roll it back so nothing of it survives.
    Rollback();
    return s;
  }
  db_ = nullptr;
  return s;
}

void Transaction::Rollback() {
  if (db_ == nullptr) return;
  if (db_->InTransaction()) db_->Exec("ROLLBACK");
  db_ = nullptr;
}

}  // namespace rollwear::storage
