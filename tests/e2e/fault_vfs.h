// Test helper of e2e_test: an SQLite VFS that wraps the platform's default
// VFS (unix) and, on demand, makes file writes fail the way the operating
// system makes them fail, so that SQLite's own error and rollback paths run
// underneath the real MillStore:
//   - kDiskFull: a write that would grow a file (database, WAL, journal,
//     temporary file) fails with SQLITE_FULL - what the unix VFS returns
//     for ENOSPC or a short write; writes inside a file's current size
//     still succeed, as on a full disk.
//   - kReadOnly: every write and truncate fails with SQLITE_IOERR_WRITE /
//     SQLITE_IOERR_TRUNCATE - what the unix VFS returns for EROFS after
//     the file system was remounted read-only under a running daemon.
//   - kNone: plain pass-through.
// This is how SQLite's own test suite injects I/O faults; PRAGMA
// max_page_count would only limit one connection that the store keeps to
// itself, and chmod does not stop root (CI runs as root).
//
// Thread-safety: InstallFaultVfs() once per process before any database is
// opened (it becomes the default VFS); SetFaultMode() may be called from
// any thread at any time (an atomic read by every write).
#ifndef ROLLWEAR_TESTS_E2E_FAULT_VFS_H_
#define ROLLWEAR_TESTS_E2E_FAULT_VFS_H_

namespace rollwear::e2e {

enum class FaultMode { kNone, kDiskFull, kReadOnly };

// Registers the VFS as the process's default; idempotent. False when SQLite
// refused it.
bool InstallFaultVfs();
void SetFaultMode(FaultMode mode);
// Writes refused since the process started (all modes).
long FaultedWrites();

}  // namespace rollwear::e2e

#endif  // ROLLWEAR_TESTS_E2E_FAULT_VFS_H_
