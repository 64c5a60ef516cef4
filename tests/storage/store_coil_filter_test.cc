// The committed-coil filter in MillStore: a coil id it does not hold is
// admitted without reading SQLite, so what it holds must be every stored
// coil - filled on open (beyond its initial size), extended by commits of
// posted and of imported coils - and a hit must still be confirmed by the
// database (same content: unchanged, other content: AlreadyExists).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeRollChange;
using testing::OpenStore;
using testing::TempDir;

// More coils than the filter's initial table holds, so opening a store
// that has them grows it several times.
constexpr int kFilterCoils = 150;

CoilIn Coil(int i, const std::string& campaign = "C1") {
  return MakeCoil("K" + std::to_string(i), campaign, i + 1, i);
}

CoilIn Changed(CoilIn c) {
  c.passes[1].length_m = std::nextafter(c.passes[1].length_m, 1e9);
  return c;
}

// Every coil of `coils` answers kUnchanged with `first`'s answers, a change
// of content AlreadyExists; nothing is counted.
void ExpectAllStored(MillStore* store, const std::vector<CoilIn>& coils,
                     const std::vector<CoilOutcome>& first) {
  const int64_t stored = store->Counters().coils;
  for (size_t i = 0; i < coils.size(); ++i) {
    StatusOr<CoilOutcome> again = store->AddCoil(coils[i]);
    ASSERT_TRUE(again.ok())
        << coils[i].coil_id << ": " << again.status().ToString();
    EXPECT_EQ(again->outcome, WriteOutcome::kUnchanged) << coils[i].coil_id;
    if (i < first.size()) {
      ASSERT_EQ(again->added.size(), first[i].added.size());
      for (size_t k = 0; k < first[i].added.size(); ++k) {
        EXPECT_EQ(again->added[k].wear_um, first[i].added[k].wear_um);
        EXPECT_EQ(again->added[k].predicted_wear_um,
                  first[i].added[k].predicted_wear_um);
      }
    }
    EXPECT_EQ(store->AddCoil(Changed(coils[i])).status().code(),
              StatusCode::kAlreadyExists)
        << coils[i].coil_id;
  }
  EXPECT_EQ(store->Counters().coils, stored);
}

TEST(StoreCoilFilterTest, CoilsOfAnEndedCampaignAreKnownAfterReopening) {
  TempDir dir;
  std::vector<CoilIn> coils;
  std::vector<CoilOutcome> first;
  {
    auto store = OpenStore(dir.File("mill.db"));
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
    for (int i = 0; i < kFilterCoils; ++i) {
      coils.push_back(Coil(i));
      StatusOr<CoilOutcome> r = store->AddCoil(coils.back());
      ASSERT_TRUE(r.ok()) << r.status().ToString();
      first.push_back(*r);
    }
    ASSERT_TRUE(store->EndCampaign("C1", 9000).ok());
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", 9500, "2")).ok());
  }
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_EQ(store->Counters().coils, kFilterCoils);
  ExpectAllStored(store.get(), coils, first);
  // An id not stored goes on to validation: C1 has ended.
  EXPECT_EQ(store->AddCoil(Coil(kFilterCoils)).status().code(),
            StatusCode::kFailedPrecondition);
  // A new coil of the open campaign, then its repeat (known from the
  // commit, not from the open).
  const CoilIn fresh = Coil(kFilterCoils, "C2");
  StatusOr<CoilOutcome> created = store->AddCoil(fresh);
  ASSERT_TRUE(created.ok()) << created.status().ToString();
  EXPECT_EQ(created->outcome, WriteOutcome::kCreated);
  ExpectAllStored(store.get(), {fresh}, {*created});
  EXPECT_EQ(store->Counters().coils, kFilterCoils + 1);
}

TEST(StoreCoilFilterTest, ImportedCoilsAreKnownBeforeAndAfterReopening) {
  TempDir dir;
  // The dataset: kFilterCoils coils of an ended campaign, from a first store.
  std::vector<CoilIn> coils;
  Dataset data;
  {
    auto source = OpenStore(dir.File("source.db"));
    ASSERT_NE(source, nullptr);
    ASSERT_TRUE(source->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
    for (int i = 0; i < kFilterCoils; ++i) {
      coils.push_back(Coil(i));
      ASSERT_TRUE(source->AddCoil(coils.back()).ok());
    }
    ASSERT_TRUE(source->EndCampaign("C1", 9000).ok());
    StatusOr<Dataset> exported = source->ExportDataset();
    ASSERT_TRUE(exported.ok()) << exported.status().ToString();
    data = std::move(exported).value();
  }
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  Status s = store->ImportDataset(data);
  ASSERT_TRUE(s.ok()) << s.ToString();
  ASSERT_EQ(store->Counters().coils, kFilterCoils);
  ExpectAllStored(store.get(), coils, {});
  // The import itself again: every coil found stored and equal.
  s = store->ImportDataset(data);
  ASSERT_TRUE(s.ok()) << s.ToString();

  store.reset();
  store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  ExpectAllStored(store.get(), coils, {});
  s = store->ImportDataset(data);
  ASSERT_TRUE(s.ok()) << s.ToString();
  // One coil changed in the dataset: the import is refused, naming it.
  Dataset changed = data;
  changed.passes.back().force_kn += 1;
  s = store->ImportDataset(changed);
  EXPECT_EQ(s.code(), StatusCode::kAlreadyExists) << s.ToString();
  EXPECT_NE(s.message().find(data.coil_ids[data.passes.back().coil]),
            std::string::npos)
      << s.ToString();
  EXPECT_EQ(store->Counters().coils, kFilterCoils);
}

}  // namespace
}  // namespace rollwear::storage
