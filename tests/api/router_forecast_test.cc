// The router's wear limits and forecast over the real MillStore on a
// SQLite file: POST /v1/limits/{stand}/{position} (token, 400 naming
// limit_um, 404 for an unknown position), GET /v1/limits, the remaining
// life in GET /v1/wear, and POST /v1/forecast (equal to posting the same
// coils then reading GET /v1/wear, to 1e-9; errors name coils[i]...).
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

class RouterForecastTest : public RouterTest {
 protected:
  json Wear() { return Parse(Get("/v1/wear")); }
  static double Rel(double a, double b) {
    return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
  }
};

TEST_F(RouterForecastTest, SetLimitNeedsTheTokenAndAValidLimit) {
  ApiOptions options;
  options.token = "s3cret";
  MakeRouter(options);
  const std::string auth = "Bearer s3cret";
  const std::string before = State();
  const json body = {{"limit_um", 320.0}, {"reason", "HSS grade"}};
  ExpectRejected(Post("/v1/limits/F6/top", body), 401, "unauthorized", nullptr,
                 before);
  ExpectRejected(Post("/v1/limits/F6/top", {{"limit_um", "a lot"}}, auth), 400,
                 "wrong_type", "limit_um", before);
  for (double bad : {0.0, -1.0, 5000.01, 1e300}) {
    ExpectRejected(Post("/v1/limits/F6/top", {{"limit_um", bad}}, auth), 400,
                   "out_of_range", "limit_um", before);
  }
  ExpectRejected(Post("/v1/limits/F6/top", json::object(), auth), 400,
                 "missing_field", "limit_um", before);
  ExpectRejected(Post("/v1/limits/F6/top", {{"limit_um", 10}, {"x", 1}}, auth),
                 400, "unknown_field", "x", before);
  ExpectRejected(Post("/v1/limits/F9/top", body, auth), 404, "not_found",
                 nullptr, before);
  ExpectRejected(Post("/v1/limits/F6/middle", body, auth), 404, "not_found",
                 nullptr, before);
  EXPECT_EQ(Get("/v1/limits/F6/top").status, 405);

  const HttpResponse ok = Post("/v1/limits/F6/top", body, auth);
  ASSERT_EQ(ok.status, 200) << ok.body;
  const json set = Parse(ok);
  EXPECT_EQ(set["stand"], "F6");
  EXPECT_EQ(set["position"], "top");
  EXPECT_EQ(set["limit_um"], 320.0);
  EXPECT_EQ(set["source"], "api");
  EXPECT_EQ(set["reason"], "HSS grade");
  EXPECT_TRUE(set["set_at"].is_string());

  const json limits = Parse(Get("/v1/limits"));
  ASSERT_EQ(limits["limits"].size(), 14u);
  int with_limit = 0;
  for (const json& l : limits["limits"]) {
    if (!l["limit_um"].is_null()) {
      ++with_limit;
      EXPECT_EQ(l["stand"], "F6");
      EXPECT_EQ(l["limit_um"], 320.0);
    }
  }
  EXPECT_EQ(with_limit, 1);
  // GET /v1/wear carries it; no coils yet, so no remaining life.
  const json wear = Wear();
  for (const json& p : wear["positions"]) {
    const bool f6top = p["stand"] == "F6" && p["position"] == "top";
    EXPECT_EQ(p["wear_limit_um"].is_null(), !f6top) << p;
    EXPECT_TRUE(p["remaining_length_m"].is_null()) << p;
    EXPECT_TRUE(p["remaining_length_interval_m"].is_null()) << p;
  }
}

TEST_F(RouterForecastTest, WearAddsRemainingLifeAfterCoils) {
  ASSERT_EQ(Post("/v1/limits/F7/bottom", {{"limit_um", 150}}).status, 200);
  for (int seq = 1; seq <= 5; ++seq) {
    ASSERT_EQ(Post("/v1/coils", CoilBody("K" + std::to_string(seq), "C1", seq))
                  .status,
              201);
  }
  const json at = Parse(Get("/v1/wear/F7/bottom"));
  const double wear = at["predicted_wear_um"];
  const double length = at["rolled_length_m"];
  ASSERT_GT(wear, 0);
  ASSERT_LT(wear, 150);
  EXPECT_NEAR(at["remaining_length_m"].get<double>(),
              (150 - wear) * length / wear, 1e-6);
  EXPECT_NEAR(at["remaining_coils"].get<double>(), (150 - wear) * 5 / wear,
              1e-9);
  const json& interval = at["remaining_length_interval_m"];
  ASSERT_EQ(interval.size(), 2u);
  EXPECT_LE(interval[0].get<double>(), at["remaining_length_m"].get<double>());
  if (!interval[1].is_null()) {
    EXPECT_GE(interval[1].get<double>(),
              at["remaining_length_m"].get<double>());
  }
}

TEST_F(RouterForecastTest, ForecastEqualsPostingThenReadingWear) {
  for (int seq = 1; seq <= 3; ++seq) {
    ASSERT_EQ(Post("/v1/coils", CoilBody("K" + std::to_string(seq), "C1", seq))
                  .status,
              201);
  }
  json coils = json::array();
  for (int seq = 4; seq <= 23; ++seq) {
    json coil = CoilBody("K" + std::to_string(seq), "C1", seq);
    coil["passes"][0]["force_kn"] = 15000.0 + 400.0 * seq;
    coil["passes"][1]["length_m"] = 500.0 + 13.0 * seq;
    coil["mill_zone"] = seq % 2 == 0 ? "east" : "west";  // an extra field
    coils.push_back(coil);
  }
  const std::string before = State();
  const HttpResponse r = Post("/v1/forecast", {{"coils", coils}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(State(), before) << "a forecast changed the state";
  const json f = Parse(r);
  ASSERT_EQ(f["positions"].size(), 4u);
  EXPECT_EQ(f["coils"], 20);
  for (const json& p : f["positions"]) {
    EXPECT_EQ(p["predicted_wear_um"].size(), 20u);
    EXPECT_EQ(p["interval_um"].size(), 20u);
    EXPECT_TRUE(p["first_crossing"].is_null());
    EXPECT_EQ(p["campaign_id"], "C1");
  }
  for (size_t i = 0; i < coils.size(); ++i) {
    ASSERT_EQ(Post("/v1/coils", coils[i]).status, 201);
    const json wear = Wear();
    ASSERT_EQ(wear["positions"].size(), 4u);
    EXPECT_EQ(wear["model_version"], f["model_version"]);
    for (size_t p = 0; p < 4; ++p) {
      const json& w = wear["positions"][p];
      const json& fp = f["positions"][p];
      ASSERT_EQ(w["roll_id"], fp["roll_id"]);
      EXPECT_LE(Rel(w["predicted_wear_um"], fp["predicted_wear_um"][i]), 1e-9)
          << p << " after coil " << i;
      EXPECT_LE(Rel(w["interval_um"][0], fp["interval_um"][i][0]), 1e-9);
      EXPECT_LE(Rel(w["interval_um"][1], fp["interval_um"][i][1]), 1e-9);
    }
  }
}

TEST_F(RouterForecastTest, FirstCrossingNamesTheCoil) {
  json coils = json::array();
  for (int seq = 1; seq <= 30; ++seq) {
    coils.push_back(CoilBody("P" + std::to_string(seq), "C1", seq));
  }
  const json free_run = Parse(Post("/v1/forecast", {{"coils", coils}}));
  const json& wear = free_run["positions"][0]["predicted_wear_um"];
  const double limit = 0.5 * (wear[16].get<double>() + wear[17].get<double>());
  ASSERT_EQ(Post("/v1/limits/F6/top", {{"limit_um", limit}}).status, 200);
  const json f = Parse(Post("/v1/forecast", {{"coils", coils}}));
  EXPECT_EQ(f["positions"][0]["wear_limit_um"], limit);
  EXPECT_EQ(f["positions"][0]["first_crossing"]["index"], 17);
  EXPECT_EQ(f["positions"][0]["first_crossing"]["coil_id"], "P18");
}

TEST_F(RouterForecastTest, ForecastErrorsNameTheCoilAndChangeNothing) {
  ASSERT_EQ(Post("/v1/coils", CoilBody("K1", "C1", 1)).status, 201);
  const std::string before = State();
  json coils = json::array();
  for (int seq = 1; seq <= 5; ++seq) {
    coils.push_back(CoilBody("P" + std::to_string(seq), "C1", seq));
  }
  // A planned coil is not yet rolled: one stored already, or planned twice,
  // is refused (posting it again would add nothing).
  json bad = coils;
  bad[2]["coil_id"] = "K1";
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 422, "inconsistent",
                 "coils[2].coil_id", before);
  bad = coils;
  bad[3]["coil_id"] = "P1";
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 400, "invalid_value",
                 "coils[3].coil_id", before);
  bad = coils;
  bad[3]["passes"][1]["force_kn"] = -3.0;
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 400, "out_of_range",
                 "coils[3].passes[1].force_kn", before);
  bad = coils;
  bad[2]["passes"][0]["force_kn"] = "high";
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 400, "wrong_type",
                 "coils[2].passes[0].force_kn", before);
  bad = coils;
  bad[1]["campaign_id"] = "C0";
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 422, "inconsistent",
                 "coils[1].campaign_id", before);
  bad = coils;
  bad[4]["passes"][0]["stand"] = "F2";
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 422, "inconsistent",
                 "coils[4].passes[0].stand", before);
  bad = coils;
  bad[0] = 7;
  ExpectRejected(Post("/v1/forecast", {{"coils", bad}}), 400, "wrong_type",
                 "coils[0]", before);
  ExpectRejected(Post("/v1/forecast", json::object()), 400, "missing_field",
                 "coils", before);
  ExpectRejected(Post("/v1/forecast", {{"coils", json::array()}}), 400,
                 "out_of_range", "coils", before);
  ExpectRejected(Post("/v1/forecast", {{"coils", 3}}), 400, "wrong_type",
                 "coils", before);
  ExpectRejected(Post("/v1/forecast", {{"coils", coils}, {"when", 1}}), 400,
                 "unknown_field", "when", before);
  ExpectRejected(PostRaw("/v1/forecast", R"({"coils": [{"coil_id": )"), 400,
                 "malformed_json", nullptr, before);
  ExpectRejected(PostRaw("/v1/forecast", R"({"coils": [], "coils": []})"), 400,
                 "invalid_value", "coils", before);
  ExpectRejected(PostRaw("/v1/forecast", R"({"coils": [], "x": 1} trailing)"),
                 400, "malformed_json", nullptr, before);
  ExpectRejected(PostRaw("/v1/forecast", "[1, 2"), 400, "malformed_json",
                 nullptr, before);
  ExpectRejected(PostRaw("/v1/forecast", "[1, 2]"), 400, "wrong_type", nullptr,
                 before);

  ApiOptions options;
  options.max_forecast_coils = 4;
  options.token = "t";
  MakeRouter(options);
  ExpectRejected(Post("/v1/forecast", {{"coils", coils}}), 401, "unauthorized",
                 nullptr, before);
  ExpectRejected(Post("/v1/forecast", {{"coils", coils}}, "Bearer t"), 413,
                 "too_many_elements", "coils", before);
  coils.erase(coils.begin());
  EXPECT_EQ(Post("/v1/forecast", {{"coils", coils}}, "Bearer t").status, 200);
}

}  // namespace
}  // namespace rollwear::api::testing
