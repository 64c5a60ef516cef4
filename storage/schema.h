// The database schema of rollwear and its migrations.
//
// The schema version lives in the one-row table `schema_version`. A
// migration is the SQL that takes a database from version N-1 to N; the
// list below is applied in order, all pending steps and the version update
// inside one transaction, so an upgrade either completes or leaves the file
// as it was. A file whose version is newer than the last migration this
// build knows is refused (FailedPrecondition) and left untouched. Adding
// a version means appending one Migration to SchemaMigrations() and bumping
// kSchemaVersion in store_types.h.
//
// Version 1 tables (see docs/architecture.md, "Storage"):
//   campaigns, mounts, coils, passes (one row per coil per stand),
//   measurements, models (versions of calibrated WearModels as JSON, one
//   flagged active), calibrations (runs and their metrics).
// Version 2 adds coils.wear: the answer a coil's first post got (the wear
// it added to each roll position and the roll's total after it), so that a
// repeat is answered in O(passes).
// Version 7 adds profile_points: the grinder's profiles across the barrel.
// Rolls' predicted state is not stored: it is recomputed from the stored
// passes of the open campaign on start and whenever the model changes.
//
// Thread-safety: stateless functions; the Db passed in must not be used by
// another thread during the call.
#ifndef ROLLWEAR_STORAGE_SCHEMA_H_
#define ROLLWEAR_STORAGE_SCHEMA_H_

#include <string>
#include <vector>

#include "core/base/status.h"
#include "storage/sqlite_db.h"

namespace rollwear::storage {

struct Migration {
  int version;              // version reached after this step (1, 2, ...)
  const char* description;  // one line
  const char* sql;          // statements, no parameters
};

// rollwear's migrations, ascending, migrations[i].version == i + 1.
const std::vector<Migration>& SchemaMigrations();

// The version recorded in the file: 0 for an empty database (no tables).
// A database with tables but no schema_version table is not rollwear's:
// FailedPrecondition.
StatusOr<int> ReadSchemaVersion(Db* db);

// Brings `db` to the last version of `migrations` (which must be ascending
// and contiguous from 1), in one transaction. Refuses a newer file with
// "database schema version N is newer than this rollwear (supports up to
// M); upgrade rollwear".
Status MigrateSchema(Db* db, const std::vector<Migration>& migrations);

// MigrateSchema with SchemaMigrations().
inline Status MigrateSchema(Db* db) {
  return MigrateSchema(db, SchemaMigrations());
}

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_SCHEMA_H_
