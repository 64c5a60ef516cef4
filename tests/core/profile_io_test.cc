// profiles.csv (optional file of the data format): read with the tiny
// dataset, written back, and each rule broken reported with file, line,
// column and field, reading nothing.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "tests/core/dataset_test_util.h"

namespace rollwear {
namespace {

using dataset_test::TinyTexts;

constexpr const char* kHeader =
    "campaign_id,stand,position,roll_id,measured_at,x_mm,wear_um\n";

StatusOr<Dataset> ReadWithProfiles(const std::string& profiles) {
  const dataset_test::DatasetTexts t = TinyTexts();
  std::istringstream c(t.campaigns), m(t.mounts), p(t.coils),
      s(t.measurements), pr(profiles);
  DatasetStreams streams{&c, &m, &p, &s, &pr};
  return ReadDatasetStreams(streams);
}

TEST(ProfileIo, PointsAreReadAndWrittenBack) {
  const std::string text = std::string(kHeader) +
                           "C1,F6,top,R601,2026-03-01T18:00:00Z,-500,160.5\n"
                           "C1,F6,top,R601,2026-03-01T18:00:00Z,0,152.4\n"
                           "C1,F6,top,R601,2026-03-01T18:00:00Z,512.5,171\n"
                           "C1,F7,bottom,R702,2026-03-01T18:30:00Z,0,-3.5\n";
  StatusOr<Dataset> d = ReadWithProfiles(text);
  ASSERT_TRUE(d.ok()) << d.status().ToString();
  ASSERT_EQ(d->profile_points.size(), 4u);
  const ProfilePoint& p = d->profile_points[2];
  EXPECT_EQ(d->campaigns[p.campaign].id, "C1");
  EXPECT_EQ(p.stand, 6);
  EXPECT_EQ(p.position, Position::kTop);
  EXPECT_EQ(p.roll_id, "R601");
  EXPECT_DOUBLE_EQ(p.x_mm, 512.5);
  EXPECT_DOUBLE_EQ(p.wear_um, 171);
  EXPECT_EQ(d->profile_points[3].position, Position::kBottom);

  const std::string dir = dataset_test::ScratchDir("rollwear_profile_io");
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(WriteDataset(*d, dir).ok());
  StatusOr<Dataset> again = ReadDataset(dir);
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  ASSERT_EQ(again->profile_points.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(again->profile_points[i].x_mm, d->profile_points[i].x_mm);
    EXPECT_EQ(again->profile_points[i].wear_um, d->profile_points[i].wear_um);
    EXPECT_EQ(again->profile_points[i].measured_at,
              d->profile_points[i].measured_at);
  }
  // Without points, no profiles.csv (and a stale one is removed).
  Dataset none = *d;
  none.profile_points.clear();
  ASSERT_TRUE(WriteDataset(none, dir).ok());
  EXPECT_FALSE(std::filesystem::exists(dir + "/profiles.csv"));
  StatusOr<Dataset> read_none = ReadDataset(dir);
  ASSERT_TRUE(read_none.ok());
  EXPECT_TRUE(read_none->profile_points.empty());
  std::filesystem::remove_all(dir);
}

struct BadProfile {
  const char* row;
  const char* expected;  // a substring of the error
};

TEST(ProfileIo, EachBrokenRuleNamesFileLineColumnAndField) {
  const BadProfile cases[] = {
      {"C1,F6,top,R999,2026-03-01T18:00:00Z,0,1",
       "profiles.csv:3:4 roll_id: roll_id must match mounts.csv"},
      {"C1,F6,top,R601,2026-03-01T13:00:00Z,0,1",
       "profiles.csv:3:5 measured_at: must not be before the end of campaign C1"},
      {"C1,F5,top,R601,2026-03-01T18:00:00Z,0,1",
       "profiles.csv:3:2 stand: no mount for F5/top of campaign 'C1'"},
      {"C9,F6,top,R601,2026-03-01T18:00:00Z,0,1", "profiles.csv:3:1 campaign_id"},
      {"C1,F6,top,R601,2026-03-01T18:00:00Z,abc,1", "profiles.csv:3:6 x_mm"},
      {"C1,F6,top,R601,2026-03-01T18:00:00Z,0,", "profiles.csv:3:7 wear_um"},
      {"C1,F6,top,R601,2026-03-01T18:00:00Z,-500,2",
       "profiles.csv:3:6 x_mm: duplicate key (campaign_id, stand, position, "
       "x_mm): F6/top of campaign 'C1' has a point at x_mm -500 on line 2"},
  };
  for (const BadProfile& c : cases) {
    const std::string text = std::string(kHeader) +
                             "C1,F6,top,R601,2026-03-01T18:00:00Z,-500,1\n" +
                             c.row + "\n";
    StatusOr<Dataset> d = ReadWithProfiles(text);
    ASSERT_FALSE(d.ok()) << c.row;
    EXPECT_NE(d.status().message().find(c.expected), std::string::npos)
        << "row " << c.row << "\n got " << d.status().message();
  }
  // A missing column is named.
  StatusOr<Dataset> d = ReadWithProfiles(
      "campaign_id,stand,position,roll_id,measured_at,x_mm\n");
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.status().message().find("wear_um"), std::string::npos)
      << d.status().message();
}

}  // namespace
}  // namespace rollwear
