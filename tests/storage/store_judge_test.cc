// The daemon's judge of a new reading (JudgeMeasurement, storage/
// store_quality.h) works on the per-stand exposures its catalog keeps; it
// must flag exactly what core's AssessDataQuality flags on the stored data
// of the same window of campaigns with the reading added, whichever way the
// campaigns came in: imported, posted coil by coil, or loaded on a reopen.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/data_quality.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "storage/store_quality.h"
#include "storage/store_sql.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::OpenStore;
using testing::TempDir;

constexpr int kWindow = 50;  // MillStoreImpl::kJudgedCampaigns
constexpr int kCampaigns = 64;
constexpr int kImported = 16;
constexpr int kReopenAfter = 40;

std::string CampaignId(int c) {
  std::string id = "J";
  id += std::to_string(100 + c);
  return id;
}

// Campaign c: its rolls, 6 + c % 9 coils (so that loads differ), ended.
void PostCampaign(MillStore* store, int c, int* coil) {
  const UnixSeconds start = 1'800'000'000 + 86'400 * c;
  ASSERT_TRUE(
      store->ApplyRollChange(MakeRollChange(CampaignId(c), start)).ok());
  for (int seq = 1; seq <= 6 + c % 9; ++seq, ++*coil) {
    ASSERT_TRUE(store
                    ->AddCoil(MakeCoil(std::to_string(*coil), CampaignId(c),
                                       seq, *coil))
                    .ok());
  }
  ASSERT_TRUE(store->EndCampaign(CampaignId(c), start + 80'000).ok());
}

// The reading of campaign c at (stand, position): wear about proportional
// to the campaign's coils with a spread, and three gauge faults planted.
double Reading(int c, int stand, Position p) {
  const int k = 4 * c + 2 * (stand - 6) + static_cast<int>(p);
  if (c == 30 && stand == 6 && p == Position::kTop) return -62.6;
  if (c == 44 && stand == 7 && p == Position::kBottom) return 9000;
  if (c == 52 && stand == 6 && p == Position::kBottom) return 0.5;
  return (6 + c % 9) * (9.0 + stand - 6) * std::exp(0.15 * std::sin(1.7 * k));
}

MeasurementIn ReadingIn(int c, int stand, Position p) {
  std::string roll = "R";
  roll += std::to_string(stand);
  roll += p == Position::kTop ? 'T' : 'B';  // MakeRollChange's roll ids
  MeasurementIn m =
      MakeMeasurement(CampaignId(c), stand, p, roll, Reading(c, stand, p));
  m.measured_at = 1'800'000'000 + 86'400 * c + 85'000;
  return m;
}

// What core's file check says of the last reading of the stored data when
// only the readings of campaigns [first, ...) stored before it count.
std::string FlagOfFileCheck(const Dataset& stored, int first, size_t row) {
  Dataset window = stored;
  window.measurements.clear();
  for (size_t i = 0; i <= row; ++i) {
    if (stored.measurements[i].campaign >= first) {
      window.measurements.push_back(stored.measurements[i]);
    }
  }
  return internal::SuspectFlags(AssessDataQuality(window)).back();
}

TEST(StoreJudgeTest, AReadingIsFlaggedAsTheFileCheckFlagsItsWindow) {
  TempDir dir;
  // The first campaigns come in by import, from a store they were posted to.
  Dataset first_part;
  {
    auto source = OpenStore(dir.File("source.db"));
    ASSERT_NE(source, nullptr);
    int coil = 0;
    for (int c = 0; c < kImported; ++c) {
      PostCampaign(source.get(), c, &coil);
      ASSERT_FALSE(HasFatalFailure());
      for (int stand : {6, 7}) {
        for (Position p : {Position::kTop, Position::kBottom}) {
          ASSERT_TRUE(source->AddMeasurement(ReadingIn(c, stand, p)).ok());
        }
      }
    }
    StatusOr<Dataset> exported = source->ExportDataset();
    ASSERT_TRUE(exported.ok()) << exported.status().ToString();
    first_part = std::move(exported).value();
  }
  const std::string path = dir.File("mill.db");
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ImportDataset(first_part).ok());
  // The rest posted as the mill and the grinder would, reopened once.
  std::vector<std::string> flags;  // of each posted reading, in order
  std::map<std::pair<int, int>, std::string> by_reading;  // (c, slot)
  int coil = 100'000;
  for (int c = kImported; c < kCampaigns; ++c) {
    if (c == kReopenAfter) {
      store.reset();
      store = OpenStore(path);
      ASSERT_NE(store, nullptr);
    }
    PostCampaign(store.get(), c, &coil);
    ASSERT_FALSE(HasFatalFailure());
    // The grinder's order varies: every other campaign F7 bottom first.
    std::vector<std::pair<int, Position>> order = {{6, Position::kTop},
                                                   {6, Position::kBottom},
                                                   {7, Position::kTop},
                                                   {7, Position::kBottom}};
    if (c % 2 == 1) std::reverse(order.begin(), order.end());
    for (const auto& [stand, p] : order) {
      std::string suspect;
      ASSERT_TRUE(store->AddMeasurement(ReadingIn(c, stand, p), &suspect).ok());
      flags.push_back(suspect);
      by_reading[{c, RollPositionSlot(stand, p)}] = suspect;
    }
  }
  StatusOr<Dataset> stored = store->ExportDataset();
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  ASSERT_EQ(stored->campaigns.size(), static_cast<size_t>(kCampaigns));
  const size_t imported_readings = 4 * kImported;
  ASSERT_EQ(stored->measurements.size(), imported_readings + flags.size());
  int flagged = 0;
  for (size_t k = 0; k < flags.size(); ++k) {
    const size_t row = imported_readings + k;
    const int c = stored->measurements[row].campaign;
    const std::string expected =
        FlagOfFileCheck(*stored, std::max(0, c + 1 - kWindow), row);
    EXPECT_EQ(flags[k], expected) << "reading " << k << " of campaign " << c;
    flagged += flags[k].empty() ? 0 : 1;
  }
  // The three planted faults, and nothing else, are flagged: the test
  // compares flags, not only empty strings.
  EXPECT_EQ(flagged, 3);
  const auto flag_of = [&](int c, int stand, Position p) {
    return by_reading[{c, RollPositionSlot(stand, p)}];
  };
  EXPECT_EQ(flag_of(30, 6, Position::kTop).rfind("negative_wear: ", 0), 0u);
  EXPECT_EQ(flag_of(44, 7, Position::kBottom).rfind("excess_wear: ", 0), 0u);
  EXPECT_EQ(flag_of(52, 6, Position::kBottom).rfind("low_wear: ", 0), 0u);
}

// A reading of an old campaign is judged among the campaigns from its own
// on (the window reaches back to it), as the file check of those would.
TEST(StoreJudgeTest, AnOldCampaignsReadingReachesBackToItsCampaign) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  int coil = 0;
  for (int c = 0; c < kWindow + 8; ++c) {
    PostCampaign(store.get(), c, &coil);
    ASSERT_FALSE(HasFatalFailure());
    if (c == 3) continue;  // measured late, below
    for (int stand : {6, 7}) {
      for (Position p : {Position::kTop, Position::kBottom}) {
        ASSERT_TRUE(store->AddMeasurement(ReadingIn(c, stand, p)).ok());
      }
    }
  }
  // Campaign 3 is older than the newest 50: its reading is judged among
  // the readings of campaigns 3 to 57.
  MeasurementIn late = ReadingIn(3, 7, Position::kTop);
  late.wear_center_um = 9000;
  std::string suspect;
  ASSERT_TRUE(store->AddMeasurement(late, &suspect).ok());
  StatusOr<Dataset> stored = store->ExportDataset();
  ASSERT_TRUE(stored.ok());
  const size_t row = stored->measurements.size() - 1;
  ASSERT_EQ(stored->measurements[row].campaign, 3);
  // Stored in row order after the newer campaigns' readings; the file
  // check of campaigns 3.. with it last gives the same flag.
  EXPECT_EQ(suspect, FlagOfFileCheck(*stored, 3, row));
  EXPECT_EQ(suspect.rfind("excess_wear: ", 0), 0u) << suspect;
}

}  // namespace
}  // namespace rollwear::storage
