#include "storage/schema.h"

#include <string>

#include "storage/store_types.h"

namespace rollwear::storage {
namespace {

// Version 1: the initial schema. Positions are 0 = top, 1 = bottom
// (core/dataset/dataset.h); times are Unix seconds; `extra` holds a row's extra
// dataset columns as a JSON object (NULL when none). ended_at is NULL
// while a campaign is open.
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE IF NOT EXISTS schema_version (
  version INTEGER NOT NULL
) STRICT;

CREATE TABLE campaigns (
  id INTEGER PRIMARY KEY,
  campaign_id TEXT NOT NULL UNIQUE,
  started_at INTEGER NOT NULL,
  ended_at INTEGER,
  extra TEXT
) STRICT;

CREATE TABLE mounts (
  id INTEGER PRIMARY KEY,
  campaign INTEGER NOT NULL REFERENCES campaigns(id),
  stand INTEGER NOT NULL CHECK (stand BETWEEN 1 AND 7),
  position INTEGER NOT NULL CHECK (position IN (0, 1)),
  roll_id TEXT NOT NULL,
  roll_type TEXT NOT NULL,
  diameter_mm REAL NOT NULL,
  hardness_hb REAL NOT NULL,
  extra TEXT,
  UNIQUE (campaign, stand, position)
) STRICT;

CREATE TABLE coils (
  id INTEGER PRIMARY KEY,
  coil_id TEXT NOT NULL UNIQUE,
  campaign INTEGER NOT NULL REFERENCES campaigns(id),
  seq INTEGER NOT NULL,
  grade TEXT NOT NULL,
  UNIQUE (campaign, seq)
) STRICT;

CREATE TABLE passes (
  id INTEGER PRIMARY KEY,
  coil INTEGER NOT NULL REFERENCES coils(id),
  campaign INTEGER NOT NULL REFERENCES campaigns(id),
  stand INTEGER NOT NULL CHECK (stand BETWEEN 1 AND 7),
  rolled_at INTEGER NOT NULL,
  force_kn REAL NOT NULL,
  width_mm REAL NOT NULL,
  length_m REAL NOT NULL,
  entry_thickness_mm REAL NOT NULL,
  exit_thickness_mm REAL NOT NULL,
  temperature_c REAL NOT NULL,
  speed_mps REAL NOT NULL,
  lubrication INTEGER NOT NULL CHECK (lubrication IN (0, 1)),
  shift_mm REAL NOT NULL,
  extra TEXT,
  UNIQUE (coil, stand)
) STRICT;
CREATE INDEX passes_by_campaign ON passes (campaign);

CREATE TABLE measurements (
  id INTEGER PRIMARY KEY,
  campaign INTEGER NOT NULL REFERENCES campaigns(id),
  stand INTEGER NOT NULL CHECK (stand BETWEEN 1 AND 7),
  position INTEGER NOT NULL CHECK (position IN (0, 1)),
  roll_id TEXT NOT NULL,
  measured_at INTEGER NOT NULL,
  wear_center_um REAL NOT NULL,
  extra TEXT,
  UNIQUE (campaign, stand, position)
) STRICT;

CREATE TABLE calibrations (
  id INTEGER PRIMARY KEY,
  status TEXT NOT NULL
    CHECK (status IN ('queued', 'running', 'done', 'failed')),
  triggered_by TEXT NOT NULL,
  law TEXT NOT NULL,
  k_option INTEGER NOT NULL,
  queued_at INTEGER NOT NULL,
  started_at INTEGER,
  finished_at INTEGER,
  coefficients_json TEXT,
  cost REAL,
  gap_train_um REAL,
  gap_val_um REAL,
  active_gap_val_um REAL,
  n_train INTEGER NOT NULL DEFAULT 0,
  n_val INTEGER NOT NULL DEFAULT 0,
  promoted INTEGER NOT NULL DEFAULT 0,
  model_version INTEGER,
  message TEXT NOT NULL DEFAULT '',
  measurement_watermark INTEGER
) STRICT;

CREATE TABLE models (
  version INTEGER PRIMARY KEY,
  created_at INTEGER NOT NULL,
  law TEXT NOT NULL,
  k_option INTEGER NOT NULL,
  gap_val_um REAL,
  calibration INTEGER REFERENCES calibrations(id),
  active INTEGER NOT NULL DEFAULT 0 CHECK (active IN (0, 1)),
  model_json TEXT NOT NULL
) STRICT;
CREATE UNIQUE INDEX models_one_active ON models (active) WHERE active = 1;
)sql";

// Version 2: each coil keeps the answer its first post got - per roll
// position it passed, the wear it added and the roll's total right after it
// (encoding in store_sql.h, EncodeCoilWear) - so that a repeated post is
// answered from the coil's row instead of replaying its campaign. NULL for
// coils stored before (a version-1 file) and, briefly, for imported ones:
// MillStore fills them in (BackfillCoilWear) in the transaction that
// imports and on Open; the partial index finds them without a scan.
constexpr const char* kSchemaV2 = R"sql(
ALTER TABLE coils ADD COLUMN wear BLOB;
CREATE INDEX coils_without_wear ON coils (campaign) WHERE wear IS NULL;
)sql";

// Version 3: passes_by_campaign goes. Every read of a campaign's passes
// reaches them through its coils (coils' (campaign, seq) index, then
// passes' (coil, stand) index), so the index only cost each pass of each
// coil one more B-tree insert and each group commit one more WAL page.
constexpr const char* kSchemaV3 = R"sql(
DROP INDEX IF EXISTS passes_by_campaign;
)sql";

// Version 4: a measurement may be flagged as suspect (a valid number that
// cannot be physical wear, docs/data-format.md "Implausible values"): NULL
// when plausible, else "<kind>: <reason>" (kind as in
// core/dataset/data_quality.h). Rows of an older file are kept unflagged.
constexpr const char* kSchemaV4 = R"sql(
ALTER TABLE measurements ADD COLUMN suspect TEXT;
)sql";

// Version 5: wear limits set through the API (POST /v1/limits/{stand}/
// {position}), one per roll position ("F6", "top"); set_at is an ISO 8601
// UTC timestamp. A limit here wins over the configuration's.
constexpr const char* kSchemaV5 = R"sql(
CREATE TABLE IF NOT EXISTS wear_limits (stand TEXT NOT NULL, position TEXT NOT NULL, limit_um REAL NOT NULL, set_at TEXT NOT NULL, reason TEXT, PRIMARY KEY (stand, position));
)sql";

// Version 6: models under control, stored diagnoses, roll look-ups.
// - models.pinned: 1 on the active row when it was activated by hand
//   (POST /v1/models/{version}/activate) and not unpinned since; calibration
//   runs and diagnosis adoptions do not replace a pinned model.
// - model_history: one row per promotion, automatic or manual (the audit
//   trail of GET /v1/models/history); `source` is calibration, nightly,
//   diagnosis or manual. Versions stored before it get one row each,
//   reason "recorded before the audit trail", at their created_at.
// - diagnoses: each finished daemon diagnosis, its JSON report and the
//   HTML report the CLI writes (core/report/diagnosis_report.h).
// - mounts_by_roll, measurements_by_roll: a roll's mounts and measurements
//   by roll_id (GET /v1/rolls/{roll_id} answers from the in-memory catalog
//   today; the indexes are for SQL readers of the file, such as export and
//   the roll shop's own queries).
constexpr const char* kSchemaV6 = R"sql(
ALTER TABLE models ADD COLUMN pinned INTEGER NOT NULL DEFAULT 0
  CHECK (pinned IN (0, 1));

CREATE TABLE model_history (
  id INTEGER PRIMARY KEY,
  version INTEGER NOT NULL REFERENCES models(version),
  previous_version INTEGER,
  source TEXT NOT NULL,
  reason TEXT NOT NULL,
  at INTEGER NOT NULL,
  pinned INTEGER NOT NULL DEFAULT 0 CHECK (pinned IN (0, 1))
) STRICT;
INSERT INTO model_history (version, previous_version, source, reason, at)
  SELECT m.version, LAG(m.version) OVER (ORDER BY m.version),
         CASE WHEN c.triggered_by = 'nightly' THEN 'nightly'
              WHEN c.triggered_by LIKE 'diagnosis%' THEN 'diagnosis'
              ELSE 'calibration' END,
         'recorded before the audit trail', m.created_at
  FROM models m LEFT JOIN calibrations c ON c.id = m.calibration
  ORDER BY m.version;

CREATE TABLE diagnoses (
  id INTEGER PRIMARY KEY,
  status TEXT NOT NULL CHECK (status IN ('done', 'failed')),
  adopt INTEGER NOT NULL DEFAULT 0,
  queued_at INTEGER NOT NULL,
  started_at INTEGER,
  finished_at INTEGER NOT NULL,
  verdict TEXT,
  message TEXT NOT NULL DEFAULT '',
  calibration INTEGER REFERENCES calibrations(id),
  report_json TEXT,
  report_html TEXT
) STRICT;

CREATE INDEX mounts_by_roll ON mounts (roll_id);
CREATE INDEX measurements_by_roll ON measurements (roll_id);
)sql";

// Version 7: grinder profiles across the barrel (POST /v1/profiles,
// profiles.csv), one row per point; a profile is the points of one
// (campaign, stand, position), `point` their order (0, 1, ...). Written in
// one transaction per profile, compared point by point on a repeat.
constexpr const char* kSchemaV7 = R"sql(
CREATE TABLE profile_points (
  id INTEGER PRIMARY KEY,
  campaign INTEGER NOT NULL REFERENCES campaigns(id),
  stand INTEGER NOT NULL CHECK (stand BETWEEN 1 AND 7),
  position INTEGER NOT NULL CHECK (position IN (0, 1)),
  point INTEGER NOT NULL CHECK (point >= 0),
  roll_id TEXT NOT NULL,
  measured_at INTEGER NOT NULL,
  x_mm REAL NOT NULL,
  wear_um REAL NOT NULL,
  UNIQUE (campaign, stand, position, point)
) STRICT;
)sql";

// Number of tables in the file (sqlite_% internals excluded).
StatusOr<int> CountTables(Db* db, bool* has_version_table) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT name FROM sqlite_schema WHERE type = 'table' "
                  "AND name NOT LIKE 'sqlite_%'"));
  int n = 0;
  *has_version_table = false;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) break;
    ++n;
    if (st.ColumnText(0) == "schema_version") *has_version_table = true;
  }
  return n;
}

}  // namespace

const std::vector<Migration>& SchemaMigrations() {
  static const std::vector<Migration>* migrations = new std::vector<Migration>{
      {1, "initial schema", kSchemaV1},
      {2, "per-coil wear answers", kSchemaV2},
      {3, "no passes_by_campaign index", kSchemaV3},
      {4, "suspect measurements", kSchemaV4},
      {5, "wear limits", kSchemaV5},
      {6, "models under control, stored diagnoses", kSchemaV6},
      {7, "grinder profiles", kSchemaV7},
  };
  static_assert(kSchemaVersion == 7,
                "kSchemaVersion must equal the last migration's version");
  return *migrations;
}

StatusOr<int> ReadSchemaVersion(Db* db) {
  bool has_version = false;
  ROLLWEAR_ASSIGN_OR_RETURN(const int tables, CountTables(db, &has_version));
  if (!has_version) {
    if (tables == 0) return 0;
    return Status::FailedPrecondition(
        "database " + db->path() +
        " is not a rollwear database (it has tables but no schema_version)");
  }
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st, db->Prepare("SELECT MAX(version) FROM schema_version"));
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
  if (!row || st.ColumnIsNull(0)) return 0;
  return static_cast<int>(st.ColumnInt(0));
}

Status MigrateSchema(Db* db, const std::vector<Migration>& migrations) {
  for (size_t i = 0; i < migrations.size(); ++i) {
    if (migrations[i].version != static_cast<int>(i) + 1) {
      return Status::Internal("schema migrations must be numbered 1, 2, ...");
    }
  }
  const int target = static_cast<int>(migrations.size());
  ROLLWEAR_ASSIGN_OR_RETURN(Transaction txn, Transaction::Begin(db));
  ROLLWEAR_ASSIGN_OR_RETURN(const int current, ReadSchemaVersion(db));
  if (current > target) {
    return Status::FailedPrecondition(
        "database schema version " + std::to_string(current) +
        " is newer than this rollwear (supports up to " +
        std::to_string(target) + "); upgrade rollwear");
  }
  if (current == target) return Status::Ok();  // nothing to do
  for (const Migration& m : migrations) {
    if (m.version <= current) continue;
    Status s = db->Exec(m.sql);
    if (!s.ok()) {
      return Status(s.code(), "schema migration to version " +
                                  std::to_string(m.version) + " (" +
                                  m.description + ") failed: " + s.message());
    }
  }
  ROLLWEAR_RETURN_IF_ERROR(db->Exec("DELETE FROM schema_version"));
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement set,
      db->Prepare("INSERT INTO schema_version (version) VALUES (?)"));
  set.BindInt(1, target);
  ROLLWEAR_RETURN_IF_ERROR(set.Run());
  return txn.Commit();
}

}  // namespace rollwear::storage
