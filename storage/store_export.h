// What `rollwear export` reads: everything a rollwear database holds as a
// core dataset (the inverse of MillStore::ImportDataset), read on a
// read-only connection in one read transaction, so that it is a consistent
// snapshot even while a daemon writes (SQLite WAL: readers do not block
// the writer nor see a half-committed group).
//
// Thread-safety: a free function; safe to call from any thread.
#ifndef ROLLWEAR_STORAGE_STORE_EXPORT_H_
#define ROLLWEAR_STORAGE_STORE_EXPORT_H_

#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"

namespace rollwear::storage {

// The dataset stored in the database at `path` (rows in the order they
// were stored, extra fields included). A campaign still open is given
// ended_at = its last pass's rolled_at (the data format has no open
// campaign). `suspect` (may be null) receives each measurement's stored
// flag ("" when plausible), parallel to the measurements. NotFound when
// there is no file, FailedPrecondition when it is not a rollwear database
// of this build's schema version.
StatusOr<Dataset> ReadDatabaseDataset(const std::string& path,
                                      std::vector<std::string>* suspect);

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_STORE_EXPORT_H_
