// DatabaseLock: one writing process per database file. `rollwear serve`
// holds it while it runs; `rollwear import` takes it for its import and is
// refused while a daemon holds it. The daemon keeps the catalog of what is
// stored in memory, so rows written by another process behind its back
// would be invisible to it (a coil for an imported campaign refused, wear
// predicted without imported coils); SQLite's own locking only keeps the
// file consistent, not the daemon's view of it.
//
// The lock is a flock(2) on "<db>-lock" next to the database, which holds
// the holder's name and pid for the message; the kernel releases it when
// the process ends, however it ends, so a crashed daemon leaves no stale
// lock behind.
//
// Thread-safety: a DatabaseLock is a move-only value; Acquire is safe to
// call from any thread.
#ifndef ROLLWEAR_STORAGE_DB_LOCK_H_
#define ROLLWEAR_STORAGE_DB_LOCK_H_

#include <string>
#include <string_view>

#include "core/base/status.h"

namespace rollwear::storage {

class DatabaseLock {
 public:
  // Takes the lock of the database at `db_path` for `holder` ("rollwear
  // serve"), without waiting. FailedPrecondition when another process holds
  // it, naming that process; IoError when the lock file cannot be opened.
  static StatusOr<DatabaseLock> Acquire(const std::string& db_path,
                                        std::string_view holder);

  DatabaseLock(DatabaseLock&& other) noexcept : fd_(other.fd_) {
    other.fd_ = -1;
  }
  DatabaseLock& operator=(DatabaseLock&& other) noexcept;
  DatabaseLock(const DatabaseLock&) = delete;
  DatabaseLock& operator=(const DatabaseLock&) = delete;
  ~DatabaseLock();

  // "<db>-lock".
  static std::string LockPath(const std::string& db_path);

 private:
  explicit DatabaseLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_DB_LOCK_H_
