#include "storage/store_export.h"

#include <filesystem>
#include <memory>

#include "storage/schema.h"
#include "storage/sqlite_db.h"
#include "storage/store_sql.h"
#include "storage/store_types.h"

namespace rollwear::storage {
namespace {

StatusOr<Dataset> ReadIn(Db* db, const std::string& path,
                         std::vector<std::string>* suspect) {
  ROLLWEAR_ASSIGN_OR_RETURN(const int version, ReadSchemaVersion(db));
  if (version != kSchemaVersion) {
    return Status::FailedPrecondition(
        "database " + path + " has schema version " + std::to_string(version) +
        ", this rollwear reads version " + std::to_string(kSchemaVersion) +
        (version < kSchemaVersion
             ? " (open it once with `rollwear serve` or `rollwear import` of "
               "this version to migrate it)"
             : " (upgrade rollwear)"));
  }
  return internal::ReadStoredDataset(db, suspect);
}

}  // namespace

StatusOr<Dataset> ReadDatabaseDataset(const std::string& path,
                                      std::vector<std::string>* suspect) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return Status::NotFound("database " + path + ": no such file");
  }
  DbOptions o;
  o.read_only = true;
  ROLLWEAR_ASSIGN_OR_RETURN(const std::unique_ptr<Db> db, Db::Open(path, o));
  // ReadStoredDataset reads in one read transaction of its own: a
  // snapshot even while a daemon commits.
  return ReadIn(db.get(), path, suspect);
}

}  // namespace rollwear::storage
