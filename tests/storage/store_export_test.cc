// ReadDatabaseDataset (what `rollwear export` writes), on real SQLite
// files: a database exported to a folder and imported into a new database
// gives the same stored data, extra fields and suspect flags included,
// read while the first store is still open.
#include "storage/store_export.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::ExpectSameDataset;
using testing::OpenStore;
using testing::SimulatedMill;
using testing::TempDir;

TEST(StoreExportTest, ExportThenImportGivesTheSameStoredData) {
  TempDir dir;
  auto a = OpenStore(dir.File("a.db"));
  ASSERT_NE(a, nullptr);
  Dataset data = SimulatedMill(7, 20, 40, {"campaign_growth"});
  ASSERT_GT(data.measurements.size(), 4u);
  data.measurements[3].wear_center_um = -60.0;  // stored flagged
  ASSERT_TRUE(a->ImportDataset(data).ok());

  std::vector<std::string> flags_a;
  StatusOr<Dataset> exported = ReadDatabaseDataset(dir.File("a.db"), &flags_a);
  ASSERT_TRUE(exported.ok()) << exported.status().ToString();
  ASSERT_EQ(flags_a.size(), exported->measurements.size());
  EXPECT_NE(flags_a[3].find("negative_wear"), std::string::npos) << flags_a[3];
  ASSERT_TRUE(WriteDataset(*exported, dir.File("out")).ok());

  StatusOr<Dataset> read = ReadDataset(dir.File("out"));
  ASSERT_TRUE(read.ok()) << read.status().ToString();
  auto b = OpenStore(dir.File("b.db"));
  ASSERT_NE(b, nullptr);
  ASSERT_TRUE(b->ImportDataset(*read).ok());
  ExpectSameDataset(*a->ExportDataset(), *b->ExportDataset());
  std::vector<std::string> flags_b;
  ASSERT_TRUE(ReadDatabaseDataset(dir.File("b.db"), &flags_b).ok());
  EXPECT_EQ(flags_b, flags_a);
  EXPECT_EQ(b->Counters().suspect_measurements, 1);
}

TEST(StoreExportTest, MissingFileIsNotFound) {
  TempDir dir;
  EXPECT_EQ(ReadDatabaseDataset(dir.File("none.db"), nullptr).status().code(),
            StatusCode::kNotFound);
}

}  // namespace
}  // namespace rollwear::storage
