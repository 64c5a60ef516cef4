// Grinder profiles in the store (schema v7, MillStore::AddProfile): stored
// with all their points, idempotent by (campaign, stand, position) - the
// same points again are kUnchanged, other points AlreadyExists - refused
// with the JSON path of the bad field and nothing stored, checked against
// the campaign as measurements are, exported with the dataset, and a
// version-6 file gains the table keeping its rows.
#include <cmath>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "storage/mill_store.h"
#include "storage/model_codec.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

constexpr UnixSeconds kStart = 1'769'000'000;
constexpr UnixSeconds kEnd = 1'775'000'000;

int64_t CountPoints(const std::string& path) {
  StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
  EXPECT_TRUE(db.ok());
  if (!db.ok()) return -1;
  StatusOr<Statement> st = (*db)->Prepare("SELECT COUNT(*) FROM profile_points");
  EXPECT_TRUE(st.ok());
  if (!st.ok() || !st->Step().ok()) return -1;
  return st->ColumnInt(0);
}

ProfileIn MakeProfile(const std::string& campaign, int stand, Position p,
                      const std::string& roll_id) {
  ProfileIn in;
  in.campaign_id = campaign;
  in.stand = stand;
  in.position = p;
  in.roll_id = roll_id;
  in.measured_at = 1'780'000'000;
  in.points = {{-600, 41.5}, {-300, 30.25}, {0, 28}, {300, 30.5}, {600, 42}};
  return in;
}

// C1 with 5 coils on F6/F7, ended at kEnd; C2 open.
void StoreCampaigns(MillStore* store) {
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", kStart)).ok());
  for (int i = 1; i <= 5; ++i) {
    ASSERT_TRUE(store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i, i)).ok());
  }
  ASSERT_TRUE(store->EndCampaign("C1", kEnd).ok());
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C2", kEnd + 3600, "b")).ok());
}

TEST(StoreProfileTest, RoundTripRepeatAndConflict) {
  TempDir dir;
  const std::string path = dir.File("mill.db");
  const ProfileIn in = MakeProfile("C1", 6, Position::kTop, "R6T");
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    StoreCampaigns(store.get());
    StatusOr<WriteOutcome> out = store->AddProfile(in);
    ASSERT_TRUE(out.ok()) << out.status().ToString();
    EXPECT_EQ(*out, WriteOutcome::kCreated);
  }
  EXPECT_EQ(CountPoints(path), 5);
  auto store = OpenStore(path);  // after a reopen, as after a restart
  ASSERT_NE(store, nullptr);
  StatusOr<WriteOutcome> again = store->AddProfile(in);
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(*again, WriteOutcome::kUnchanged);
  ProfileIn other = in;
  other.points[3].wear_um = 31;
  StatusOr<WriteOutcome> conflict = store->AddProfile(other);
  ASSERT_FALSE(conflict.ok());
  EXPECT_EQ(conflict.status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(conflict.status().message().rfind("campaign_id: the profile of F6/top", 0),
            0u)
      << conflict.status().message();
  other = in;
  other.points.pop_back();  // fewer points is other content too
  EXPECT_EQ(store->AddProfile(other).status().code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(CountPoints(path), 5);

  StatusOr<Dataset> d = store->ExportDataset();
  ASSERT_TRUE(d.ok());
  ASSERT_EQ(d->profile_points.size(), 5u);
  for (size_t i = 0; i < 5; ++i) {
    const ProfilePoint& p = d->profile_points[i];
    EXPECT_EQ(d->campaigns[p.campaign].id, "C1");
    EXPECT_EQ(p.stand, 6);
    EXPECT_EQ(p.position, Position::kTop);
    EXPECT_EQ(p.roll_id, "R6T");
    EXPECT_EQ(p.measured_at, in.measured_at);
    EXPECT_EQ(p.x_mm, in.points[i].x_mm);
    EXPECT_EQ(p.wear_um, in.points[i].wear_um);
  }
}

TEST(StoreProfileTest, BadFieldsNameTheirPathAndStoreNothing) {
  TempDir dir;
  const std::string path = dir.File("mill.db");
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  StoreCampaigns(store.get());
  struct Case {
    std::function<void(ProfileIn*)> edit;
    StatusCode code;
    std::string prefix;
  };
  const Case cases[] = {
      {[](ProfileIn* p) { p->points.clear(); }, StatusCode::kInvalidArgument,
       "points: "},
      {[](ProfileIn* p) { p->points[3].x_mm = 1000.5; },
       StatusCode::kInvalidArgument, "points[3].x_mm: must lie on the barrel"},
      {[](ProfileIn* p) { p->points[2].wear_um = std::nan(""); },
       StatusCode::kInvalidArgument, "points[2].wear_um: "},
      {[](ProfileIn* p) { p->points[4].x_mm = -600; },
       StatusCode::kInvalidArgument, "points[4].x_mm: duplicate"},
      {[](ProfileIn* p) { p->stand = 9; }, StatusCode::kInvalidArgument,
       "stand: "},
      {[](ProfileIn* p) { p->campaign_id = "C9"; }, StatusCode::kNotFound,
       "campaign_id: unknown campaign C9"},
      {[](ProfileIn* p) { p->roll_id = "R6B"; },
       StatusCode::kFailedPrecondition, "roll_id: roll R6B was not mounted"},
      {[](ProfileIn* p) { p->measured_at = kEnd - 1; },
       StatusCode::kFailedPrecondition, "measured_at: "},
      {[](ProfileIn* p) { p->campaign_id = "C2"; p->roll_id = "R6Tb"; },
       StatusCode::kFailedPrecondition, "campaign_id: "},
  };
  for (const Case& c : cases) {
    ProfileIn in = MakeProfile("C1", 6, Position::kTop, "R6T");
    c.edit(&in);
    StatusOr<WriteOutcome> out = store->AddProfile(in);
    ASSERT_FALSE(out.ok()) << c.prefix;
    EXPECT_EQ(out.status().code(), c.code) << out.status().ToString();
    EXPECT_EQ(out.status().message().rfind(c.prefix, 0), 0u)
        << out.status().message();
  }
  EXPECT_EQ(CountPoints(path), 0);
}

// A version-6 file (no profile_points) is migrated on open; its rows stay.
TEST(StoreProfileTest, VersionSixFileGainsTheTable) {
  TempDir dir;
  const std::string path = dir.File("v6.db");
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    StoreCampaigns(store.get());
  }
  {
    StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)->Exec("DROP TABLE profile_points; "
                            "UPDATE schema_version SET version = 6")
                    .ok());
  }
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  EXPECT_EQ(store->Counters().coils, 5);
  StatusOr<WriteOutcome> out =
      store->AddProfile(MakeProfile("C1", 7, Position::kBottom, "R7B"));
  ASSERT_TRUE(out.ok()) << out.status().ToString();
  EXPECT_EQ(CountPoints(path), 5);
}

// The live rolls' profile sums are rebuilt on start from the stored passes:
// the profile after a reopen equals the one before, exactly; with no
// calibrated shape it is "uncalibrated" (g = 1): the centre slice reads
// the centre wear.
TEST(StoreProfileTest, ProfileStateAfterRestartEqualsTheStateBefore) {
  TempDir dir;
  const std::string path = dir.File("mill.db");
  ProfileWear before;
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", kStart)).ok());
    for (int i = 1; i <= 20; ++i) {
      ASSERT_TRUE(
          store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i, i)).ok());
    }
    StatusOr<ProfileWear> p =
        Mounted(*store).WearProfileAt(7, Position::kBottom);
    ASSERT_TRUE(p.ok()) << p.status().ToString();
    before = *p;
  }
  EXPECT_FALSE(before.shape.has_value());
  ASSERT_EQ(before.profile.x_mm.size(), 201u);
  EXPECT_EQ(before.centre.coils, 20);
  EXPECT_NEAR(before.profile.wear_um[100], before.centre.predicted_wear_um,
              1e-9 * before.centre.predicted_wear_um);
  auto store = OpenStore(path);
  ASSERT_NE(store, nullptr);
  StatusOr<ProfileWear> after =
      Mounted(*store).WearProfileAt(7, Position::kBottom);
  ASSERT_TRUE(after.ok()) << after.status().ToString();
  EXPECT_EQ(after->profile.wear_um, before.profile.wear_um);
  EXPECT_EQ(after->profile.lo_um, before.profile.lo_um);
  EXPECT_EQ(after->profile.hi_um, before.profile.hi_um);
  EXPECT_EQ(Mounted(*store).WearProfileAt(5, Position::kTop).status().code(),
            StatusCode::kNotFound);
}

// A model version's profile shape is stored in its JSON and read back
// exactly; a model JSON without one (every model before schema 7) has none.
TEST(StoreProfileTest, ModelJsonCarriesTheProfileShape) {
  ProfileFit fit;
  fit.shape.beta2 = 0.125;
  fit.shape.beta4 = -0.0625;
  fit.shape.alpha = {0.3, 0.15, 1.0 / 3};
  fit.std_error = {0.01, 0.02, 0.03, 0.04, 0.05};
  fit.residual_sd_um = 3.25;
  fit.train.n_points = 400;
  fit.train.gap_um = 2.5;
  WearModel model;
  const std::string without = EncodeModelJson(model, std::nullopt);
  StatusOr<std::optional<ProfileFit>> none = DecodeProfileShape(without);
  ASSERT_TRUE(none.ok()) << none.status().ToString();
  EXPECT_FALSE(none->has_value());
  const std::string with = EncodeModelJson(model, fit);
  StatusOr<std::optional<ProfileFit>> back = DecodeProfileShape(with);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_TRUE(back->has_value());
  EXPECT_EQ((*back)->shape.beta2, fit.shape.beta2);
  EXPECT_EQ((*back)->shape.beta4, fit.shape.beta4);
  EXPECT_EQ((*back)->shape.alpha, fit.shape.alpha);
  EXPECT_EQ((*back)->std_error, fit.std_error);
  EXPECT_EQ((*back)->residual_sd_um, fit.residual_sd_um);
  EXPECT_EQ((*back)->train.n_points, 400);
  // The covariance the served interval reads (profile_interval.h) comes
  // back exactly; a shape stored without it gets its diagonal se^2.
  fit.covariance[0][1] = fit.covariance[1][0] = -1.5e-4;
  fit.covariance[2][2] = 9e-4;
  fit.within_roll_sd_um = 2.75;
  StatusOr<std::optional<ProfileFit>> cov =
      DecodeProfileShape(EncodeModelJson(model, fit));
  ASSERT_TRUE(cov.ok() && cov->has_value());
  EXPECT_EQ((*cov)->covariance, fit.covariance);
  EXPECT_EQ((*cov)->within_roll_sd_um, 2.75);
  std::string old = with;
  // (the centre model has a "covariance" of its own: the profile's is
  // the one after "profile")
  const size_t at = old.find("\"covariance\"", old.find("\"profile\""));
  ASSERT_NE(at, std::string::npos);
  old.replace(at, 12, "\"covarianxe\"");
  StatusOr<std::optional<ProfileFit>> legacy = DecodeProfileShape(old);
  ASSERT_TRUE(legacy.ok() && legacy->has_value());
  EXPECT_DOUBLE_EQ((*legacy)->covariance[4][4], 0.05 * 0.05);
  EXPECT_EQ((*legacy)->covariance[0][1], 0);
  std::string bad = EncodeModelJson(model, fit);
  bad.replace(bad.find("\"covariance\":[[", bad.find("\"profile\"")), 15, "\"covariance\":[[1,");
  const Status bad_status = DecodeProfileShape(bad).status();
  EXPECT_EQ(bad_status.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(bad_status.message().find("profile.covariance[0]"),
            std::string::npos)
      << bad_status.message();
  std::string broken = with;
  broken.replace(broken.find("\"residual_sd_um\""), 16, "\"residual_sd_xx\"");
  EXPECT_EQ(DecodeProfileShape(broken).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace rollwear::storage
