// The successful paths of every endpoint through Router::Handle on the real
// MillStore: status codes, answer shapes, idempotent repeats, wear
// accumulation, calibration jobs, models, health and metrics.
#include <string>

#include <gtest/gtest.h>

#include "api/codec.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

TEST_F(RouterTest, RollChangeIs201ThenIdempotent200) {
  const json body = RollChangeBody("C2", "2026-03-02T06:00:00Z", "-b");
  const HttpResponse first = Post("/v1/roll-changes", body);
  EXPECT_EQ(first.status, 201) << first.body;
  EXPECT_EQ(Parse(first).value("campaign_id", ""), "C2");
  const std::string after = State();
  const HttpResponse again = Post("/v1/roll-changes", body);
  EXPECT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(State(), after);
  // The new campaign's rolls are the mounted ones now.
  const json wear = Parse(Get("/v1/wear"));
  ASSERT_EQ(wear["positions"].size(), 4u) << wear.dump();
  for (const json& p : wear["positions"]) {
    EXPECT_EQ(p["campaign_id"], "C2");
    EXPECT_EQ(p["coils"], 0);
  }
}

TEST_F(RouterTest, CoilIs201WithTheWearAddedPerRollPosition) {
  const HttpResponse r = Post("/v1/coils", CoilBody("K1", "C1", 1));
  ASSERT_EQ(r.status, 201) << r.body;
  const json answer = Parse(r);
  EXPECT_EQ(answer["coil_id"], "K1");
  EXPECT_EQ(answer["outcome"], "created");
  ASSERT_EQ(answer["added"].size(), 4u) << r.body;  // F6, F7 x top, bottom
  for (const json& a : answer["added"]) {
    EXPECT_GT(a["wear_um"].get<double>(), 0) << a.dump();
    EXPECT_DOUBLE_EQ(a["wear_um"].get<double>(),
                     a["predicted_wear_um"].get<double>());
  }
  // A second coil adds the same wear again (same passes).
  const json second = Parse(Post("/v1/coils", CoilBody("K2", "C1", 2)));
  ASSERT_EQ(second["added"].size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(second["added"][i]["predicted_wear_um"].get<double>(),
                2 * answer["added"][i]["wear_um"].get<double>(), 1e-9);
  }
}

TEST_F(RouterTest, WearListsEveryMountedRollAndOnePosition) {
  ASSERT_EQ(Post("/v1/coils", CoilBody("K1", "C1", 1)).status, 201);
  const HttpResponse r = Get("/v1/wear");
  ASSERT_EQ(r.status, 200);
  const json wear = Parse(r);
  ASSERT_TRUE(wear.contains("model_version"));
  ASSERT_EQ(wear["positions"].size(), 4u) << r.body;
  const json& p = wear["positions"][0];
  EXPECT_EQ(p["stand"], "F6");
  EXPECT_EQ(p["position"], "top");
  EXPECT_EQ(p["roll_id"], "R-F6-top");
  EXPECT_EQ(p["campaign_id"], "C1");
  EXPECT_EQ(p["coils"], 1);
  EXPECT_DOUBLE_EQ(p["rolled_length_m"].get<double>(), 820.5);
  const double wear_um = p["predicted_wear_um"].get<double>();
  EXPECT_GT(wear_um, 0);
  ASSERT_EQ(p["interval_um"].size(), 2u);
  EXPECT_LE(p["interval_um"][0].get<double>(), wear_um);
  EXPECT_GE(p["interval_um"][1].get<double>(), wear_um);

  const HttpResponse one = Get("/v1/wear/F6/top");
  ASSERT_EQ(one.status, 200) << one.body;
  const json position = Parse(one);
  EXPECT_EQ(position["roll_id"], "R-F6-top");
  EXPECT_DOUBLE_EQ(position["predicted_wear_um"].get<double>(), wear_um);
  EXPECT_EQ(Get("/v1/wear/F7/bottom").status, 200);
}

TEST_F(RouterTest, MeasurementIs201ThenIdempotent200) {
  ASSERT_EQ(Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
                .status,
            200);
  const json m = MeasurementBody("C1", "F7", "bottom", "R-F7-bottom", 85.5);
  EXPECT_EQ(Post("/v1/measurements", m).status, 201);
  EXPECT_EQ(store_->Counters().measurements, 1);
  EXPECT_EQ(Post("/v1/measurements", m).status, 200);
  EXPECT_EQ(store_->Counters().measurements, 1);
}

TEST_F(RouterTest, ExtraFieldsAreStoredAsPartOfTheContent) {
  json coil = CoilBody("K1", "C1", 1);
  coil["line"] = "HSM-2";
  coil["passes"][0]["roll_gap_mm"] = 3.3;
  EXPECT_EQ(Post("/v1/coils", coil).status, 201);
  // The same body again (members in another order would do too): unchanged.
  EXPECT_EQ(Post("/v1/coils", coil).status, 200);
  // The extra fields are part of the stored content (docs/api.md "Extra
  // fields"): without them, or with another value, the coil conflicts.
  EXPECT_EQ(Post("/v1/coils", CoilBody("K1", "C1", 1)).status, 409);
  coil["passes"][0]["roll_gap_mm"] = 3.4;
  EXPECT_EQ(Post("/v1/coils", coil).status, 409);
  EXPECT_EQ(store_->Counters().coils, 1);
}

TEST_F(RouterTest, CalibrationIsQueuedWith202AndListed) {
  int64_t notified = 0;
  ApiOptions options;
  options.on_calibration_queued = [&notified](int64_t id) { notified = id; };
  MakeRouter(options);
  const HttpResponse r = PostRaw("/v1/calibrations", "");
  ASSERT_EQ(r.status, 202) << r.body;
  const int64_t id = Parse(r)["id"].get<int64_t>();
  EXPECT_GT(id, 0);
  EXPECT_EQ(notified, id);

  const json record = Parse(Get("/v1/calibrations/" + std::to_string(id)));
  EXPECT_EQ(record["id"], id);
  EXPECT_EQ(record["status"], "queued");
  EXPECT_EQ(record["model"], "wang");
  EXPECT_EQ(record["option"], 1);
  EXPECT_TRUE(record.contains("coefficients"));
  EXPECT_TRUE(record.contains("gap_val_um"));
  EXPECT_EQ(record["promoted"], false);

  const HttpResponse other =
      Post("/v1/calibrations", {{"model", "cao"}, {"option", 3}});
  ASSERT_EQ(other.status, 202) << other.body;
  const json list = Parse(Get("/v1/calibrations"));
  ASSERT_EQ(list["calibrations"].size(), 2u) << list.dump();
  HttpRequest limited;
  limited.method = "GET";
  limited.path = "/v1/calibrations";
  limited.params["limit"] = "1";
  EXPECT_EQ(Parse(router_->Handle(limited))["calibrations"].size(), 1u);
  limited.params["limit"] = "0";
  EXPECT_EQ(router_->Handle(limited).status, 400);
}

TEST_F(RouterTest, ActiveModelIsThePriorBeforeAnyCalibration) {
  const HttpResponse r = Get("/v1/models/active");
  ASSERT_EQ(r.status, 200) << r.body;
  const json model = Parse(r);
  EXPECT_EQ(model["version"], 0);
  EXPECT_EQ(model["model"], "wang");
  EXPECT_EQ(model["option"], 1);
  EXPECT_TRUE(model["coefficients"].is_object());
  EXPECT_TRUE(model["terms"].is_array());
  EXPECT_TRUE(model.contains("created_at"));
  EXPECT_EQ(Get("/v1/models").status, 200);
}

TEST_F(RouterTest, HealthAndMetrics) {
  const HttpResponse health = Get("/healthz");
  EXPECT_EQ(health.status, 200);
  EXPECT_EQ(Parse(health)["status"], "ok");

  ASSERT_EQ(Post("/v1/coils", CoilBody("K1", "C1", 1)).status, 201);
  router_->metrics()->ObserveRequest(RouteId::kCoils, 201, 0.002);
  router_->metrics()->ObserveCalibration(true, 12.5);
  const HttpResponse m = Get("/metrics");
  ASSERT_EQ(m.status, 200);
  EXPECT_EQ(m.content_type.rfind("text/plain", 0), 0u);
  for (const char* name :
       {"rollwear_coils_ingested_total 1",
        "rollwear_http_request_duration_seconds_bucket{route=\"/v1/coils\","
        "method=\"POST\",le=\"0.0025\"} 1",
        "rollwear_http_request_duration_seconds_count{route=\"/v1/coils\","
        "method=\"POST\"} 1",
        "rollwear_calibration_runs_total{status=\"done\"} 1",
        "rollwear_calibration_runs_total{status=\"failed\"} 0",
        "rollwear_calibration_duration_seconds_bucket{le=\"30\"} 1",
        "rollwear_validation_gap_um NaN", "rollwear_group_commits_total",
        "rollwear_coils_stored 1", "rollwear_up 1"}) {
    EXPECT_NE(m.body.find(name), std::string::npos) << name << "\n" << m.body;
  }
}

TEST_F(RouterTest, HeadIsAnsweredLikeGet) {
  EXPECT_EQ(Send("HEAD", "/v1/wear", "").status, 200);
}

}  // namespace
}  // namespace rollwear::api::testing
