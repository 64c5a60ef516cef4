// DatabaseLock: one holder at a time, a clear message naming the holder,
// released when the holder lets go.
#include "storage/db_lock.h"

#include <unistd.h>

#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::TempDir;

TEST(DatabaseLockTest, SecondHolderIsRefusedUntilTheFirstLetsGo) {
  TempDir dir;
  const std::string db = dir.File("mill.db");
  std::optional<StatusOr<DatabaseLock>> serve =
      DatabaseLock::Acquire(db, "rollwear serve");
  ASSERT_TRUE(serve->ok()) << serve->status().ToString();

  StatusOr<DatabaseLock> import = DatabaseLock::Acquire(db, "rollwear import");
  ASSERT_FALSE(import.ok());
  EXPECT_EQ(import.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(import.status().message(),
            "database " + db + " is in use by rollwear serve, pid " +
                std::to_string(::getpid()) + " (lock " + db +
                "-lock): stop it first, or send the data to the running "
                "daemon through its API (rollwear replay)");

  serve.reset();  // the daemon stops
  import = DatabaseLock::Acquire(db, "rollwear import");
  EXPECT_TRUE(import.ok()) << import.status().ToString();
  // Another database is another lock.
  EXPECT_TRUE(DatabaseLock::Acquire(dir.File("other.db"), "x").ok());
}

}  // namespace
}  // namespace rollwear::storage
