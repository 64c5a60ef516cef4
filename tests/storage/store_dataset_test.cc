// ImportDataset / ExportDataset: the round trip ReadDataset(dir) -> import
// -> export gives the same Dataset (labels, indices, numbers, extra
// columns); import is all-or-nothing and idempotent, and conflicts with
// stored content name the key.
#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "core/sim/simulator.h"
#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::ExpectSameDataset;
using testing::MakeCoil;
using testing::MakeRollChange;
using testing::OpenStore;
using testing::TempDir;

const std::string kTiny = std::string(ROLLWEAR_TEST_DATA_DIR) + "/tiny";

Dataset ReadTiny(DatasetLines* lines = nullptr) {
  StatusOr<Dataset> d = ReadDataset(kTiny, lines);
  EXPECT_TRUE(d.ok()) << d.status().ToString();
  return d.ok() ? std::move(d).value() : Dataset{};
}

// Everything observable that an import could change.
void ExpectUnchanged(MillStore* store, const Dataset& before,
                     const StoreCounters& counters) {
  StatusOr<Dataset> after = store->ExportDataset();
  ASSERT_TRUE(after.ok());
  ExpectSameDataset(before, *after);
  const StoreCounters n = store->Counters();
  EXPECT_EQ(n.coils, counters.coils);
  EXPECT_EQ(n.campaigns, counters.campaigns);
  EXPECT_EQ(n.measurements, counters.measurements);
  EXPECT_EQ(n.commits, counters.commits);
}

TEST(StoreDatasetTest, TinyFolderRoundTripsWithExtraColumns) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  const Dataset tiny = ReadTiny();
  ASSERT_FALSE(tiny.pass_extra.numeric_names.empty());
  ASSERT_FALSE(tiny.pass_extra.factor_names.empty());
  Status s = store->ImportDataset(tiny);
  ASSERT_TRUE(s.ok()) << s.ToString();
  StatusOr<Dataset> out = store->ExportDataset();
  ASSERT_TRUE(out.ok()) << out.status().ToString();
  ExpectSameDataset(tiny, *out);
  const StoreCounters n = store->Counters();
  EXPECT_EQ(n.campaigns, 2);
  EXPECT_EQ(n.coils, static_cast<int64_t>(tiny.coil_ids.size()));
  EXPECT_EQ(n.measurements, 6);
  EXPECT_EQ(n.measurements_since_last_calibration, 6);
  EXPECT_EQ(n.commits, 1);  // one transaction

  // Written back to a folder and read again: the same dataset.
  ASSERT_TRUE(WriteDataset(*out, dir.File("export")).ok());
  StatusOr<Dataset> reread = ReadDataset(dir.File("export"));
  ASSERT_TRUE(reread.ok()) << reread.status().ToString();
  ExpectSameDataset(tiny, *reread);

  // Survives a restart.
  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  out = store->ExportDataset();
  ASSERT_TRUE(out.ok());
  ExpectSameDataset(tiny, *out);
}

TEST(StoreDatasetTest, SimulatedFolderRoundTrips) {
  TempDir dir;
  SimulatorOptions o;
  o.seed = 7;
  o.num_campaigns = 12;
  o.coils_per_campaign = 40;
  o.missing_measurement_fraction = 0.2;
  StatusOr<Simulation> sim = Simulate(o);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  ASSERT_TRUE(WriteDataset(sim->data, dir.File("sim")).ok());
  StatusOr<Dataset> folder = ReadDataset(dir.File("sim"));
  ASSERT_TRUE(folder.ok()) << folder.status().ToString();
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ImportDataset(*folder).ok());
  StatusOr<Dataset> out = store->ExportDataset();
  ASSERT_TRUE(out.ok());
  ExpectSameDataset(*folder, *out);
}

TEST(StoreDatasetTest, ImportIsIdempotentAndMergesNewRows) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  Dataset tiny = ReadTiny();
  ImportCounts first;
  ASSERT_TRUE(store->ImportDataset(tiny, nullptr, &first).ok());
  EXPECT_EQ(first.campaigns.added, 2);
  EXPECT_EQ(first.mounts.added, 8);
  EXPECT_EQ(first.coils.added, 5);
  EXPECT_EQ(first.measurements.added, 6);
  EXPECT_EQ(first.coils.unchanged + first.measurements.unchanged, 0);
  StatusOr<Dataset> before = store->ExportDataset();
  ASSERT_TRUE(before.ok());
  const StoreCounters counters = store->Counters();
  // The same content again: nothing new, everything unchanged.
  ImportCounts counts;
  Status s = store->ImportDataset(tiny, nullptr, &counts);
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(counts.campaigns.added, 0);
  EXPECT_EQ(counts.campaigns.unchanged, 2);
  EXPECT_EQ(counts.mounts.added, 0);
  EXPECT_EQ(counts.mounts.unchanged, 8);
  EXPECT_EQ(counts.coils.added, 0);
  EXPECT_EQ(counts.coils.unchanged, 5);
  EXPECT_EQ(counts.measurements.added, 0);
  EXPECT_EQ(counts.measurements.unchanged, 6);
  EXPECT_EQ(store->Counters().coils, counters.coils);
  EXPECT_EQ(store->Counters().measurements, counters.measurements);
  EXPECT_EQ(store->Counters().campaigns, counters.campaigns);
  StatusOr<Dataset> after = store->ExportDataset();
  ASSERT_TRUE(after.ok());
  ExpectSameDataset(*before, *after);

  // Dataset with one measurement less, plus a third campaign: only the
  // new campaign is added.
  Dataset more = tiny;
  more.measurements.pop_back();
  for (auto& col : more.measurement_extra.numeric) col.pop_back();
  for (auto& col : more.measurement_extra.factor) col.pop_back();
  more.campaigns.push_back(Campaign{"C3", 1'780'000'000, 1'780'003'600});
  for (auto& col : more.campaign_extra.numeric) col.push_back(0);
  for (auto& col : more.campaign_extra.factor) col.push_back(0);
  s = store->ImportDataset(more, nullptr, &counts);
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(counts.campaigns.added, 1);
  EXPECT_EQ(counts.campaigns.unchanged, 2);
  EXPECT_EQ(counts.measurements.added, 0);
  EXPECT_EQ(counts.measurements.unchanged, 5);
  EXPECT_EQ(store->Counters().campaigns, counters.campaigns + 1);
  EXPECT_EQ(store->Counters().measurements, counters.measurements);
}

TEST(StoreDatasetTest, ABrokenRowLeavesTheDatabaseUnchanged) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("L1", 1000)).ok());
  ASSERT_TRUE(store->AddCoil(MakeCoil("LK1", "L1", 1)).ok());
  StatusOr<Dataset> before = store->ExportDataset();
  ASSERT_TRUE(before.ok());
  const StoreCounters counters = store->Counters();

  Dataset broken = ReadTiny();
  broken.passes.back().force_kn = -1;  // the last row of all
  Status s = store->ImportDataset(broken);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message().rfind("passes[9].force_kn: must be > 0", 0), 0u)
      << s.message();
  ExpectUnchanged(store.get(), *before, counters);

  broken = ReadTiny();
  broken.passes[3].exit_thickness_mm = broken.passes[3].entry_thickness_mm;
  s = store->ImportDataset(broken);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("passes[3].exit_thickness_mm"), std::string::npos);
  ExpectUnchanged(store.get(), *before, counters);

  broken = ReadTiny();
  broken.measurements[1].roll_id = "nope";
  s = store->ImportDataset(broken);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("measurements[1].roll_id"), std::string::npos);
  ExpectUnchanged(store.get(), *before, counters);

  broken = ReadTiny();
  broken.campaigns[1].id = broken.campaigns[0].id;
  s = store->ImportDataset(broken);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  ExpectUnchanged(store.get(), *before, counters);
}

TEST(StoreDatasetTest, AnInconsistentDatasetLeavesTheDatabaseUnchanged) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("L1", 1000)).ok());
  StatusOr<Dataset> before = store->ExportDataset();
  ASSERT_TRUE(before.ok());
  const StoreCounters counters = store->Counters();

  // Campaign C1's F7 rolls said to sit at F5: its F7 passes have no roll.
  Dataset broken = ReadTiny();
  for (Mount& m : broken.mounts) {
    if (m.campaign == 0 && m.stand == 7) m.stand = 5;
  }
  Status s = store->ImportDataset(broken);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(),
            "passes[1].stand: no roll mounted at F7 in campaign C1; its rolls "
            "are at F5/top, F5/bottom, F6/top, F6/bottom (coil K1001 at F7)");
  ExpectUnchanged(store.get(), *before, counters);

  broken = ReadTiny();
  broken.measurements[2].measured_at = broken.campaigns[0].ended_at - 1;
  s = store->ImportDataset(broken);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(),
            "measurements[2].measured_at: must not be before the end of "
            "campaign C1 (2026-03-01T14:00:00Z): a roll is measured after it "
            "is taken out, got 2026-03-01T13:59:59Z");
  ExpectUnchanged(store.get(), *before, counters);
}

TEST(StoreDatasetTest, ConflictWithStoredContentNamesTheKey) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ImportDataset(ReadTiny()).ok());
  StatusOr<Dataset> before = store->ExportDataset();
  ASSERT_TRUE(before.ok());
  const StoreCounters counters = store->Counters();

  // A new campaign plus one coil whose stored content differs. With the
  // lines the folder was read with, the conflict names file and line.
  DatasetLines lines;
  Dataset next = ReadTiny(&lines);
  next.campaigns.push_back(Campaign{"C3", 1'780'000'000, 1'780'003'600});
  next.passes[4].force_kn += 0.5;  // K1002 at F7, line 6
  Status s = store->ImportDataset(next, &lines, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kAlreadyExists) << s.ToString();
  EXPECT_EQ(s.message(),
            "coils.csv:6 coil_id: coil K1002 is already stored with different "
            "content");
  ExpectUnchanged(store.get(), *before, counters);

  next = ReadTiny();
  next.measurements[0].wear_center_um = 1;
  s = store->ImportDataset(next, &lines, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(s.message(),
            "measurements.csv:2 campaign_id: F6/top of campaign C1 is already "
            "measured with different content");
  ExpectUnchanged(store.get(), *before, counters);

  next = ReadTiny();
  next.campaigns[1].ended_at += 1;
  s = store->ImportDataset(next, &lines, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kAlreadyExists);
  EXPECT_NE(s.message().find("campaigns.csv:3 campaign_id: campaign C2"),
            std::string::npos)
      << s.message();
  ExpectUnchanged(store.get(), *before, counters);

  next = ReadTiny();
  next.mounts[0].diameter_mm += 1;  // R601, C1, F6/top
  s = store->ImportDataset(next, &lines, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(s.message(),
            "mounts.csv:2 stand: F6/top of campaign C1 is already stored with "
            "different content");
  ExpectUnchanged(store.get(), *before, counters);

  next = ReadTiny();
  next.coil_ids[1] = "K9";  // K1003 (seq 3 of C1, first on line 4) renamed
  s = store->ImportDataset(next, &lines, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(s.message(),
            "coils.csv:4 seq: seq 3 of campaign C1 is already used by coil "
            "K1003 (this is coil K9)");
  ExpectUnchanged(store.get(), *before, counters);

  next = ReadTiny();
  next.campaigns[1].ended_at += 1;
  // Without lines (a dataset built in code) the row is named by index.
  s = store->ImportDataset(next);
  EXPECT_NE(s.message().find("campaigns[1].campaign_id: campaign C2"),
            std::string::npos)
      << s.message();
  ExpectUnchanged(store.get(), *before, counters);

  // An open campaign in the store is not the ended one of a dataset.
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C3", 1'780'000'000)).ok());
  next = ReadTiny();
  next.campaigns.push_back(Campaign{"C3", 1'780'000'000, 1'780'003'600});
  s = store->ImportDataset(next);
  EXPECT_EQ(s.code(), StatusCode::kAlreadyExists);
}

TEST(StoreDatasetTest, ExportGivesAnOpenCampaignItsLastCoilAsEnd) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
  StatusOr<Dataset> d = store->ExportDataset();
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->campaigns[0].ended_at, 1000);
  const CoilIn coil = MakeCoil("K1", "C1", 1, 3);
  ASSERT_TRUE(store->AddCoil(coil).ok());
  d = store->ExportDataset();
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->campaigns[0].ended_at, coil.rolled_at);
  EXPECT_EQ(d->passes.size(), 2u);
  EXPECT_EQ(d->coil_ids, std::vector<std::string>{"K1"});
}

}  // namespace
}  // namespace rollwear::storage
