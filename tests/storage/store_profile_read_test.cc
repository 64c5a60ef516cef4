// MillStore::RecentProfiles (storage/mill_store_profile_read.cc), the
// dashboard's measured against predicted profiles: the stored points of the
// newest ended campaigns with a profile, newest first, each with the active
// model's profile at its x - the profile the live roll had when its
// campaign ended (WearProfileAt), read between slices - and "uncalibrated"
// while the model has no profile shape.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/barrel_profile.h"
#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

constexpr UnixSeconds kReadStart = 1'769'000'000;
constexpr UnixSeconds kMeasured = 1'780'000'000;

ProfileIn Profile(const std::string& campaign, int stand, Position p,
                  const std::string& roll_id) {
  ProfileIn in;
  in.campaign_id = campaign;
  in.stand = stand;
  in.position = p;
  in.roll_id = roll_id;
  in.measured_at = kMeasured;
  in.points = {{-600, 41.5}, {-300, 30.25}, {0, 28}, {317, 30.5}, {600, 42}};
  return in;
}

TEST(StoreProfileReadTest,
     NewestEndedCampaignsWithTheLiveProfileAtTheirPoints) {
  TempDir dir;
  auto store = OpenStore(dir.File("mill.db"));
  ASSERT_NE(store, nullptr);
  // C1 and C2 with 6 coils each (different numbers), C3 open.
  std::vector<ProfileWear> live;  // C1's F6/top, then C2's F7/bottom
  for (int c = 1; c <= 2; ++c) {
    const std::string id = "C" + std::to_string(c);
    const UnixSeconds start = kReadStart + c * 86'400;
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange(id, start, id)).ok());
    for (int i = 1; i <= 6; ++i) {
      ASSERT_TRUE(store
                      ->AddCoil(MakeCoil(id + "K" + std::to_string(i), id, i,
                                         i + 3 * c))
                      .ok());
    }
    StatusOr<ProfileWear> p =
        c == 1 ? Mounted(*store).WearProfileAt(6, Position::kTop)
               : Mounted(*store).WearProfileAt(7, Position::kBottom);
    ASSERT_TRUE(p.ok()) << p.status().ToString();
    live.push_back(*p);
    ASSERT_TRUE(store->EndCampaign(id, start + 43'200).ok());
  }
  ASSERT_TRUE(
      store->ApplyRollChange(MakeRollChange("C3", kReadStart + 4 * 86'400, "C3"))
          .ok());
  ASSERT_TRUE(
      store->AddProfile(Profile("C1", 6, Position::kTop, "R6TC1")).ok());
  ASSERT_TRUE(
      store->AddProfile(Profile("C2", 7, Position::kBottom, "R7BC2")).ok());

  StatusOr<std::vector<MeasuredProfile>> recent = store->RecentProfiles(5);
  ASSERT_TRUE(recent.ok()) << recent.status().ToString();
  ASSERT_EQ(recent->size(), 2u);
  EXPECT_EQ((*recent)[0].campaign_id, "C2");  // newest first
  EXPECT_EQ((*recent)[1].campaign_id, "C1");
  const ProfileGrid grid;
  for (int k = 0; k < 2; ++k) {
    const MeasuredProfile& m = (*recent)[k];
    const ProfileWear& at_end = live[1 - k];
    EXPECT_EQ(m.stand, at_end.centre.stand);
    EXPECT_EQ(m.position, at_end.centre.position);
    EXPECT_EQ(m.roll_id, at_end.centre.roll_id);
    EXPECT_FALSE(m.calibrated);
    ASSERT_EQ(m.x_mm.size(), 5u);
    EXPECT_EQ(m.measured_um[3], 30.5);
    for (size_t i = 0; i < m.x_mm.size(); ++i) {
      const double expected =
          grid.Interpolate(at_end.profile.wear_um, m.x_mm[i]);
      // The coils' strips cover x = -300..317, not +-600 (no wear there).
      if (std::abs(m.x_mm[i]) < 500) {
        EXPECT_GT(expected, 1) << m.campaign_id << " x " << m.x_mm[i];
      } else {
        EXPECT_EQ(expected, 0) << m.campaign_id << " x " << m.x_mm[i];
      }
      EXPECT_NEAR(m.predicted_um[i], expected, 1e-9 * std::max(1.0, expected))
          << m.campaign_id << " x " << m.x_mm[i];
    }
  }
  // The newest only; none.
  StatusOr<std::vector<MeasuredProfile>> one = store->RecentProfiles(1);
  ASSERT_TRUE(one.ok());
  ASSERT_EQ(one->size(), 1u);
  EXPECT_EQ((*one)[0].campaign_id, "C2");
  StatusOr<std::vector<MeasuredProfile>> none = store->RecentProfiles(0);
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->empty());
}

}  // namespace
}  // namespace rollwear::storage
