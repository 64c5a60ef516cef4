// Wear limits and the forecast through the real `rollwear serve` process:
// limits from the environment (ROLLWEAR_WEAR_LIMIT_UM and a per-position
// key), one set over HTTP with the token (401 without), which survives a
// kill -9; POST /v1/forecast equals posting the same coils and reading
// GET /v1/wear, to 1e-9.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

const json* LimitAt(const json& limits, const std::string& stand,
                    const std::string& position) {
  for (const json& l : limits["limits"]) {
    if (l["stand"] == stand && l["position"] == position) return &l;
  }
  return nullptr;
}

double Rel(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
}

TEST(LimitsServeTest, LimitsSurviveKill9AndForecastEqualsPosting) {
  TempDir dir;
  std::string error;
  ASSERT_TRUE(Simulate(dir / "data", 2, 5, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok()) << data.status().ToString();
  const std::vector<std::string> env = {"ROLLWEAR_TOKEN=tok",
                                        "ROLLWEAR_WEAR_LIMIT_UM=900",
                                        "ROLLWEAR_WEAR_LIMIT_UM_F7_BOTTOM=700"};
  json answer;
  {
    Daemon daemon(dir / "m.db", dir / "serve1.log", 0, {}, env);
    ASSERT_TRUE(daemon.Start(&error)) << error;
    ASSERT_EQ(HttpPost(daemon.url(), "/v1/roll-changes",
                       RollChangeJson(*data, 0).dump(), &answer, "tok"),
              201)
        << answer.dump();
    const std::vector<int> coils = CoilsOf(*data, 0);
    ASSERT_GT(coils.size(), 40u);
    for (size_t i = 0; i < 20; ++i) {
      ASSERT_EQ(HttpPost(daemon.url(), "/v1/coils",
                         CoilJson(*data, coils[i]).dump(), &answer, "tok"),
                201);
    }
    const std::string limit = R"({"limit_um": 612.5, "reason": "test"})";
    EXPECT_EQ(HttpPost(daemon.url(), "/v1/limits/F6/top", limit, &answer), 401);
    ASSERT_EQ(
        HttpPost(daemon.url(), "/v1/limits/F6/top", limit, &answer, "tok"), 200)
        << answer.dump();

    // The next 20 coils, forecast then posted one by one.
    json schedule = json::array();
    for (size_t i = 20; i < 40; ++i)
      schedule.push_back(CoilJson(*data, coils[i]));
    json forecast;
    ASSERT_EQ(HttpPost(daemon.url(), "/v1/forecast",
                       json{{"coils", schedule}}.dump(), &forecast, "tok"),
              200)
        << forecast.dump();
    ASSERT_EQ(forecast["positions"].size(), 4u);
    for (size_t i = 0; i < schedule.size(); ++i) {
      ASSERT_EQ(HttpPost(daemon.url(), "/v1/coils", schedule[i].dump(), &answer,
                         "tok"),
                201);
      json wear;
      ASSERT_EQ(HttpGet(daemon.url(), "/v1/wear", &wear), 200);
      for (size_t p = 0; p < 4; ++p) {
        const json& w = wear["positions"][p];
        const json& f = forecast["positions"][p];
        EXPECT_LE(Rel(w["predicted_wear_um"], f["predicted_wear_um"][i]), 1e-9);
        EXPECT_LE(Rel(w["interval_um"][0], f["interval_um"][i][0]), 1e-9);
        EXPECT_LE(Rel(w["interval_um"][1], f["interval_um"][i][1]), 1e-9);
        EXPECT_EQ(w["wear_limit_um"], f["wear_limit_um"]);
      }
    }
    daemon.Kill9();
  }
  Daemon restarted(dir / "m.db", dir / "serve2.log", 0, {}, env);
  ASSERT_TRUE(restarted.Start(&error)) << error;
  json limits;
  ASSERT_EQ(HttpGet(restarted.url(), "/v1/limits", &limits), 200);
  const json* f6top = LimitAt(limits, "F6", "top");
  ASSERT_NE(f6top, nullptr) << limits.dump();
  EXPECT_EQ((*f6top)["limit_um"], 612.5);
  EXPECT_EQ((*f6top)["source"], "api");
  EXPECT_EQ((*f6top)["reason"], "test");
  EXPECT_EQ((*LimitAt(limits, "F7", "bottom"))["limit_um"], 700);
  EXPECT_EQ((*LimitAt(limits, "F7", "bottom"))["source"], "config");
  EXPECT_EQ((*LimitAt(limits, "F1", "top"))["limit_um"], 900);
  json at;
  ASSERT_EQ(HttpGet(restarted.url(), "/v1/wear/F6/top", &at), 200);
  EXPECT_EQ(at["wear_limit_um"], 612.5);
  EXPECT_TRUE(at["remaining_length_m"].is_number()) << at.dump();
}

}  // namespace
}  // namespace rollwear::e2e
