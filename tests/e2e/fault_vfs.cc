#include "tests/e2e/fault_vfs.h"

#include <atomic>
#include <mutex>

#include <sqlite3.h>

namespace rollwear::e2e {
namespace {

std::atomic<int> g_mode{static_cast<int>(FaultMode::kNone)};
std::atomic<long> g_faulted{0};
sqlite3_vfs* g_real = nullptr;
sqlite3_vfs g_vfs;
sqlite3_io_methods g_methods;

// Our file object, with the real VFS's file object right behind it.
struct FaultFile {
  sqlite3_file base;
};

sqlite3_file* Real(sqlite3_file* f) {
  return reinterpret_cast<sqlite3_file*>(reinterpret_cast<FaultFile*>(f) + 1);
}

FaultMode Mode() { return static_cast<FaultMode>(g_mode.load()); }

int Close(sqlite3_file* f) { return Real(f)->pMethods->xClose(Real(f)); }

int Read(sqlite3_file* f, void* buf, int n, sqlite3_int64 off) {
  return Real(f)->pMethods->xRead(Real(f), buf, n, off);
}

int Write(sqlite3_file* f, const void* buf, int n, sqlite3_int64 off) {
  sqlite3_file* r = Real(f);
  switch (Mode()) {
    case FaultMode::kNone:
      break;
    case FaultMode::kDiskFull: {
      sqlite3_int64 size = 0;
      if (r->pMethods->xFileSize(r, &size) != SQLITE_OK || off + n > size) {
        ++g_faulted;
        return SQLITE_FULL;
      }
      break;
    }
    case FaultMode::kReadOnly:
      ++g_faulted;
      return SQLITE_IOERR_WRITE;
  }
  return r->pMethods->xWrite(r, buf, n, off);
}

int Truncate(sqlite3_file* f, sqlite3_int64 size) {
  if (Mode() == FaultMode::kReadOnly) {
    ++g_faulted;
    return SQLITE_IOERR_TRUNCATE;
  }
  return Real(f)->pMethods->xTruncate(Real(f), size);
}

int Sync(sqlite3_file* f, int flags) {
  return Real(f)->pMethods->xSync(Real(f), flags);
}
int FileSize(sqlite3_file* f, sqlite3_int64* size) {
  return Real(f)->pMethods->xFileSize(Real(f), size);
}
int Lock(sqlite3_file* f, int level) {
  return Real(f)->pMethods->xLock(Real(f), level);
}
int Unlock(sqlite3_file* f, int level) {
  return Real(f)->pMethods->xUnlock(Real(f), level);
}
int CheckReservedLock(sqlite3_file* f, int* out) {
  return Real(f)->pMethods->xCheckReservedLock(Real(f), out);
}
int FileControl(sqlite3_file* f, int op, void* arg) {
  return Real(f)->pMethods->xFileControl(Real(f), op, arg);
}
int SectorSize(sqlite3_file* f) {
  return Real(f)->pMethods->xSectorSize(Real(f));
}
int DeviceCharacteristics(sqlite3_file* f) {
  return Real(f)->pMethods->xDeviceCharacteristics(Real(f));
}
int ShmMap(sqlite3_file* f, int region, int size, int extend,
           void volatile** out) {
  return Real(f)->pMethods->xShmMap(Real(f), region, size, extend, out);
}
int ShmLock(sqlite3_file* f, int offset, int n, int flags) {
  return Real(f)->pMethods->xShmLock(Real(f), offset, n, flags);
}
void ShmBarrier(sqlite3_file* f) { Real(f)->pMethods->xShmBarrier(Real(f)); }
int ShmUnmap(sqlite3_file* f, int delete_flag) {
  return Real(f)->pMethods->xShmUnmap(Real(f), delete_flag);
}
int Fetch(sqlite3_file* f, sqlite3_int64 off, int n, void** out) {
  return Real(f)->pMethods->xFetch(Real(f), off, n, out);
}
int Unfetch(sqlite3_file* f, sqlite3_int64 off, void* p) {
  return Real(f)->pMethods->xUnfetch(Real(f), off, p);
}

int Open(sqlite3_vfs*, sqlite3_filename name, sqlite3_file* f, int flags,
         int* out_flags) {
  sqlite3_file* r = Real(f);
  r->pMethods = nullptr;
  const int rc = g_real->xOpen(g_real, name, r, flags, out_flags);
  // SQLite calls xClose only when pMethods is set; mirror the real file.
  f->pMethods = r->pMethods != nullptr ? &g_methods : nullptr;
  return rc;
}

}  // namespace

bool InstallFaultVfs() {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] {
    g_real = sqlite3_vfs_find(nullptr);
    if (g_real == nullptr) return;
    g_vfs = *g_real;  // every other entry point forwards as is
    g_vfs.zName = "rollwear_fault";
    g_vfs.szOsFile = static_cast<int>(sizeof(FaultFile)) + g_real->szOsFile;
    g_vfs.xOpen = Open;
    g_vfs.pNext = nullptr;
    g_methods = sqlite3_io_methods{3,
                                   Close,
                                   Read,
                                   Write,
                                   Truncate,
                                   Sync,
                                   FileSize,
                                   Lock,
                                   Unlock,
                                   CheckReservedLock,
                                   FileControl,
                                   SectorSize,
                                   DeviceCharacteristics,
                                   ShmMap,
                                   ShmLock,
                                   ShmBarrier,
                                   ShmUnmap,
                                   Fetch,
                                   Unfetch};
    ok = sqlite3_vfs_register(&g_vfs, /*makeDflt=*/1) == SQLITE_OK;
  });
  return ok;
}

void SetFaultMode(FaultMode mode) { g_mode.store(static_cast<int>(mode)); }

long FaultedWrites() { return g_faulted.load(); }

}  // namespace rollwear::e2e
