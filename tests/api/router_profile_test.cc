// Grinder profiles over the API (docs/api.md, POST /v1/profiles): 201 when
// stored, 200 for the same profile again, 409 for other points under the
// same key; a bad field is a 400 naming its JSON path and stores nothing;
// a token is needed as for every POST.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

json ProfileBody(const std::string& campaign_id, const std::string& stand,
                 const std::string& position, const std::string& roll_id) {
  json points = json::array();
  for (double x : {-700.0, -350.0, 0.0, 350.0, 700.0}) {
    points.push_back({{"x_mm", x}, {"wear_um", 30 + std::abs(x) / 50}});
  }
  return {{"campaign_id", campaign_id}, {"stand", stand},
          {"position", position},       {"roll_id", roll_id},
          {"measured_at", "2026-03-02T10:00:00Z"}, {"points", points}};
}

class ProfileRouterTest : public RouterTest {
 protected:
  void EndC1() {
    for (int i = 1; i <= 3; ++i) {
      ASSERT_EQ(
          Post("/v1/coils", CoilBody("K" + std::to_string(i), "C1", i)).status,
          201);
    }
    ASSERT_EQ(
        Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
            .status,
        200);
  }
  // Profile points stored (the export of the store).
  size_t StoredPoints() {
    StatusOr<Dataset> d = store_->ExportDataset();
    EXPECT_TRUE(d.ok());
    return d.ok() ? d->profile_points.size() : 0;
  }
};

TEST_F(ProfileRouterTest, CreatedThenRepeatedThenConflict) {
  ASSERT_NO_FATAL_FAILURE(EndC1());
  const json body = ProfileBody("C1", "F6", "top", "R-F6-top");
  const HttpResponse r = Post("/v1/profiles", body);
  ASSERT_EQ(r.status, 201) << r.body;
  const json answer = Parse(r);
  EXPECT_EQ(answer["outcome"], "created");
  EXPECT_EQ(answer["points"], 5);
  EXPECT_EQ(answer["stand"], "F6");
  EXPECT_EQ(answer["roll_id"], "R-F6-top");
  const HttpResponse again = Post("/v1/profiles", body);
  ASSERT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(Parse(again)["outcome"], "unchanged");
  json other = body;
  other["points"][2]["wear_um"] = 31.5;
  const std::string before = State();
  ExpectRejected(Post("/v1/profiles", other), 409, "conflict", nullptr,
                 before);
  EXPECT_EQ(StoredPoints(), 5u);
}

TEST_F(ProfileRouterTest, BadFieldsAre400NamingTheirPathAndStoreNothing) {
  ASSERT_NO_FATAL_FAILURE(EndC1());
  const std::string before = State();
  const json good = ProfileBody("C1", "F6", "top", "R-F6-top");
  json b = good;
  b["points"][3]["x_mm"] = 1000.5;  // off the 2,000 mm barrel
  ExpectRejected(Post("/v1/profiles", b), 400, "invalid_value",
                 "points[3].x_mm", before);
  b = good;
  b["points"][1]["wear_um"] = "12";
  ExpectRejected(Post("/v1/profiles", b), 400, "wrong_type",
                 "points[1].wear_um", before);
  b = good;
  b["points"][4].erase("x_mm");
  ExpectRejected(Post("/v1/profiles", b), 400, "missing_field",
                 "points[4].x_mm", before);
  b = good;
  b["points"] = json::array();
  ExpectRejected(Post("/v1/profiles", b), 400, "invalid_value", "points",
                 before);
  b = good;
  b["points"][0] = 3;
  ExpectRejected(Post("/v1/profiles", b), 400, "wrong_type", "points[0]",
                 before);
  // Non-finite wear: JSON has no NaN, but 1e999 reads as infinity.
  std::string text = good.dump();
  const std::string first = "\"wear_um\":44.0";
  ASSERT_NE(text.find(first), std::string::npos) << text;
  text.replace(text.find(first), first.size(), "\"wear_um\":1e999");
  ExpectRejected(PostRaw("/v1/profiles", text), 400, "invalid_value",
                 "points[0].wear_um", before);
  b = good;
  b["stand"] = "F9";
  ExpectRejected(Post("/v1/profiles", b), 400, "invalid_value", "stand",
                 before);
  b = good;
  b["roll_id"] = "R-F6-bottom";
  ExpectRejected(Post("/v1/profiles", b), 422, "inconsistent", "roll_id",
                 before);
  b = good;
  b["campaign_id"] = "C9";
  ExpectRejected(Post("/v1/profiles", b), 404, "not_found", nullptr, before);
  EXPECT_EQ(StoredPoints(), 0u);
}

TEST_F(ProfileRouterTest, ARunningCampaignIs422AndATokenIsNeeded) {
  const std::string before = State();
  ExpectRejected(Post("/v1/profiles", ProfileBody("C1", "F6", "top", "R-F6-top")),
                 422, "inconsistent", "campaign_id", before);
  ASSERT_NO_FATAL_FAILURE(EndC1());
  ApiOptions options;
  options.token = "s3cret-token";
  MakeRouter(options);
  const json body = ProfileBody("C1", "F7", "bottom", "R-F7-bottom");
  const std::string ended = State();
  ExpectRejected(Post("/v1/profiles", body), 401, "unauthorized", nullptr,
                 ended);
  EXPECT_EQ(Post("/v1/profiles", body, "Bearer s3cret-token").status, 201);
}

}  // namespace
}  // namespace rollwear::api::testing
