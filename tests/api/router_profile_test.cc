// Grinder profiles over the API (docs/api.md, POST /v1/profiles): 201 when
// stored, 200 for the same profile again, 409 for other points under the
// same key; a bad field is a 400 naming its JSON path and stores nothing;
// a token is needed as for every POST.
#include <cmath>
#include <string>
#include <utility>

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

// Uncalibrated (no profile shape in the model): g = 1, so every slice the
// strips covered (width 1250 mm at shift -35 mm: x in [35 - 625, 35 + 625]
// on the top roll, [-35 - 625, -35 + 625] on the bottom) wears the centre
// wear, nothing outside; the answer says "uncalibrated" and its interval
// is wider than the centre's. 404 once nothing is mounted.
TEST_F(ProfileRouterTest, UncalibratedProfileIsUniformUnderTheStrips) {
  for (int i = 1; i <= 3; ++i) {
    ASSERT_EQ(
        Post("/v1/coils", CoilBody("K" + std::to_string(i), "C1", i)).status,
        201);
  }
  for (const auto& [position, centre] :
       {std::pair<std::string, double>{"top", 35}, {"bottom", -35}}) {
    const HttpResponse c = Get("/v1/wear/F6/" + position);
    ASSERT_EQ(c.status, 200) << c.body;
    const json centre_answer = Parse(c);
    const double w = centre_answer["predicted_wear_um"];
    ASSERT_GT(w, 0);
    const HttpResponse r = Get("/v1/wear/F6/" + position + "/profile");
    ASSERT_EQ(r.status, 200) << r.body;
    const json a = Parse(r);
    EXPECT_EQ(a["shape"], "uncalibrated");
    EXPECT_TRUE(a["coefficients"].is_null());
    EXPECT_EQ(a["roll_id"], "R-F6-" + position);
    EXPECT_EQ(a["campaign_id"], "C1");
    EXPECT_EQ(a["coils"], 3);
    EXPECT_EQ(a["centre_wear_um"], w);
    const json& x = a["x_mm"];
    const json& p = a["predicted_wear_um"];
    const json& iv = a["interval_um"];
    ASSERT_EQ(x.size(), 201u);  // 2,000 mm barrel, 10 mm slices
    ASSERT_EQ(p.size(), 201u);
    ASSERT_EQ(iv.size(), 201u);
    EXPECT_EQ(x[0], -1000);
    EXPECT_EQ(x[200], 1000);
    int covered = 0;
    for (size_t j = 0; j < x.size(); ++j) {
      const double xj = x[j];
      if (std::abs(xj - centre) < 625) {
        ++covered;
        EXPECT_NEAR(p[j].get<double>(), w, 1e-9 * w) << xj;
        EXPECT_LT(iv[j][0].get<double>(), p[j].get<double>());
        EXPECT_GT(iv[j][1].get<double>(), p[j].get<double>());
      } else if (std::abs(xj - centre) > 625) {
        EXPECT_EQ(p[j].get<double>(), 0) << xj;
      }
    }
    EXPECT_EQ(covered, 124);  // x = -580 ... 650 (top)
    // Widened: the centre's interval and 1.96 * 20 % of the profile in
    // quadrature (core/model/profile_interval.h), at x = 0 where P = W.
    const json& ci = centre_answer["interval_um"];
    const double below = w - ci[0].get<double>();
    const double above = ci[1].get<double>() - w;
    const double shape = 1.959963984540054 * 0.2 * w;
    EXPECT_NEAR(iv[100][0].get<double>(),
                w - std::sqrt(below * below + shape * shape), 1e-9 * w);
    EXPECT_NEAR(iv[100][1].get<double>(),
                w + std::sqrt(above * above + shape * shape), 1e-9 * w);
  }
  ASSERT_EQ(Get("/v1/wear/F9/top/profile").status, 404);
  ASSERT_EQ(
      Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
          .status,
      200);
  const HttpResponse gone = Get("/v1/wear/F6/top/profile");
  EXPECT_EQ(gone.status, 404) << gone.body;
}

}  // namespace
}  // namespace rollwear::api::testing
