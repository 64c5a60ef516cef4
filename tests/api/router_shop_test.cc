// The roll shop's endpoints over the real store on a SQLite file: models
// under control (GET /v1/models/{version}, POST .../activate with its
// token, reason and unknown-version errors, GET /v1/models/history), rolls
// (GET /v1/rolls, GET /v1/rolls/{roll_id}, the roll page) and stored
// diagnoses served after a restart (GET /v1/diagnoses[/{id}[/report]]).
#include <chrono>
#include <thread>

#include "core/sim/simulator.h"
#include "engine/calibration_runs.h"
#include "engine/wear_prediction.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

class ShopRouterTest : public RouterTest {
 public:
  // Replaces the fixture's store by one at `db` holding a simulated mill.
  void UseSimulatedMill(const std::string& db, int campaigns) {
    router_.reset();
    diagnoses_.reset();
    store_.reset();
    db_ = dir_ + "/" + db;
    StatusOr<std::unique_ptr<storage::MillStore>> store =
        engine::OpenStore(db_);
    ASSERT_TRUE(store.ok());
    store_ = std::move(store).value();
    SimulatorOptions so;
    so.seed = 41;
    so.num_campaigns = campaigns;
    StatusOr<Simulation> sim = Simulate(so);
    ASSERT_TRUE(sim.ok());
    ASSERT_TRUE(store_->ImportDataset(sim->data).ok());
    MakeRouter(ApiOptions());
  }

  // Version 1 from a calibration run, version 2 the same model proposed by
  // a diagnosis (equal validation gap: promoted).
  void TwoVersions() {
    StatusOr<int64_t> id = store_->EnqueueCalibration("api", WearLaw::kWang, 1);
    ASSERT_TRUE(id.ok());
    ASSERT_TRUE(engine::CalibrationRuns(&*store_).Run(*id).ok());
    ASSERT_EQ(store_->ActiveModel()->version, 1);
    StatusOr<Dataset> data = store_->ExportDataset();
    ASSERT_TRUE(data.ok());
    auto run = engine::CalibrationRuns(&*store_).Propose(
        "diagnosis 1", "wang", 1, store_->ActiveModel()->wear_model, *data, 1);
    ASSERT_TRUE(run.ok());
    ASSERT_TRUE(run->promoted) << run->message;
    ASSERT_EQ(store_->ActiveModel()->version, 2);
  }

  std::string db_;
};

// Every version an answer names can be read: before the first promotion
// the answers name version 0, the prior (never stored), and
// GET /v1/models/0 serves it; after promotions it is still served, no
// longer active, with the same coefficients; it cannot be activated.
TEST_F(ShopRouterTest, TheVersionEveryAnswerNamesCanBeRead) {
  ASSERT_NO_FATAL_FAILURE(UseSimulatedMill("prior.db", 30));
  ApiOptions options;
  options.token = "s3cret";
  MakeRouter(options);
  const json active = Parse(Get("/v1/models/active"));
  ASSERT_EQ(active["version"], 0) << active.dump();
  EXPECT_EQ(Parse(Get("/v1/wear"))["model_version"], 0);
  HttpResponse r = Get("/v1/models/0");
  ASSERT_EQ(r.status, 200) << r.body;
  const json prior = Parse(r);
  EXPECT_EQ(prior, active);
  EXPECT_EQ(prior["run"], nullptr);
  EXPECT_EQ(prior["active"], true);

  ASSERT_NO_FATAL_FAILURE(TwoVersions());
  r = Get("/v1/models/0");
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Parse(r)["version"], 0);
  EXPECT_EQ(Parse(r)["active"], false);
  EXPECT_EQ(Parse(r)["coefficients"], prior["coefficients"]);
  EXPECT_EQ(Parse(r)["model"], prior["model"]);
  const std::string before = State();
  ExpectRejected(Get("/v1/models/-1"), 404, "not_found", nullptr, before);
  ExpectRejected(
      Post("/v1/models/0/activate", json{{"reason", "back"}}, "Bearer s3cret"),
      404, "not_found", nullptr, before);
  EXPECT_EQ(Parse(Get("/v1/models/active"))["version"], 2);
}

TEST_F(ShopRouterTest, ModelsAreListedReadAndActivatedWithTokenAndReason) {
  ASSERT_NO_FATAL_FAILURE(UseSimulatedMill("models.db", 30));
  ASSERT_NO_FATAL_FAILURE(TwoVersions());
  ApiOptions options;
  options.token = "s3cret";
  MakeRouter(options);
  const std::string auth = "Bearer s3cret";

  json list = Parse(Get("/v1/models"));
  ASSERT_EQ(list["models"].size(), 2u) << list.dump();
  EXPECT_EQ(list["models"][0]["version"], 2);
  EXPECT_EQ(list["models"][0]["run"]["source"], "diagnosis");
  EXPECT_EQ(list["models"][1]["run"]["source"], "calibration");
  EXPECT_GT(list["models"][1]["run"]["gap_train_um"].get<double>(), 0);
  EXPECT_EQ(list["models"][1]["pinned"], false);

  HttpResponse r = Get("/v1/models/1");
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Parse(r)["version"], 1);
  EXPECT_EQ(Parse(r)["active"], false);
  EXPECT_EQ(Parse(r)["coefficients"], list["models"][1]["coefficients"]);
  const std::string before = State();
  ExpectRejected(Get("/v1/models/99"), 404, "not_found", nullptr, before);
  ExpectRejected(Get("/v1/models/x1"), 404, "not_found", nullptr, before);

  // Errors change nothing.
  const json body{{"reason", "v2 over-predicts F7"}};
  ExpectRejected(Post("/v1/models/1/activate", body), 401, "unauthorized",
                 nullptr, before);
  ExpectRejected(Post("/v1/models/1/activate", body, "Bearer wrong"), 401,
                 "unauthorized", nullptr, before);
  ExpectRejected(Post("/v1/models/99/activate", body, auth), 404, "not_found",
                 nullptr, before);
  ExpectRejected(Post("/v1/models/1/activate", json::object(), auth), 400,
                 "missing_field", "reason", before);
  ExpectRejected(PostRaw("/v1/models/1/activate", "", auth), 400,
                 "missing_field", "reason", before);
  ExpectRejected(Post("/v1/models/1/activate", json{{"reason", " "}}, auth),
                 400, "out_of_range", "reason", before);
  ExpectRejected(Post("/v1/models/1/activate", json{{"reason", 3}}, auth), 400,
                 "wrong_type", "reason", before);
  ExpectRejected(
      Post("/v1/models/1/activate", json{{"reason", "x"}, {"pin", "no"}}, auth),
      400, "wrong_type", "pin", before);
  EXPECT_EQ(Get("/v1/models/1/activate").status, 405);
  EXPECT_EQ(Parse(Get("/v1/models/active"))["version"], 2);
  ASSERT_EQ(Parse(Get("/v1/models/history"))["history"].size(), 2u);

  r = Post("/v1/models/1/activate", body, auth);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Parse(r)["version"], 1);
  EXPECT_EQ(Parse(r)["pinned"], true);
  const json active = Parse(Get("/v1/models/active"));
  EXPECT_EQ(active["version"], 1);
  EXPECT_EQ(active["pinned"], true);
  EXPECT_EQ(Parse(Get("/v1/wear"))["model_version"], 1);

  const json history = Parse(Get("/v1/models/history"))["history"];
  ASSERT_EQ(history.size(), 3u) << history.dump();
  EXPECT_EQ(history[0]["version"], 1);
  EXPECT_EQ(history[0]["previous_version"], 2);
  EXPECT_EQ(history[0]["source"], "manual");
  EXPECT_EQ(history[0]["reason"], "v2 over-predicts F7");
  EXPECT_EQ(history[0]["pinned"], true);
  EXPECT_TRUE(history[0]["at"].is_string());
  EXPECT_EQ(history[2]["previous_version"], nullptr);
  HttpRequest limited;
  limited.method = "GET";
  limited.path = "/v1/models/history";
  limited.params["limit"] = "1";
  EXPECT_EQ(Parse(router_->Handle(limited))["history"].size(), 1u);
  limited.params["limit"] = "0";
  const HttpResponse bad_limit = router_->Handle(limited);
  EXPECT_EQ(bad_limit.status, 400);
  EXPECT_EQ(Parse(bad_limit)["error"]["field"], "limit");

  r = Post("/v1/models/1/activate",
           json{{"reason", "trust the nightly run again"}, {"pin", false}},
           auth);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Parse(Get("/v1/models/active"))["pinned"], false);
}

TEST_F(RouterTest, RollsShowEachMountAndTheInventory) {
  for (int seq = 1; seq <= 4; ++seq) {
    ASSERT_EQ(Post("/v1/coils", CoilBody("A" + std::to_string(seq), "C1", seq))
                  .status,
              201);
  }
  const json end_c1 = Parse(Get("/v1/wear/F6/top"));
  ASSERT_EQ(
      Post("/v1/campaigns/C1/end", json{{"ended_at", "2026-03-01T12:00:00Z"}})
          .status,
      200);
  ASSERT_EQ(Post("/v1/measurements",
                 MeasurementBody("C1", "F6", "top", "R-F6-top", 37.5))
                .status,
            201);
  ASSERT_EQ(
      Post("/v1/roll-changes", RollChangeBody("C2", "2026-03-03T06:00:00Z"))
          .status,
      201);
  ASSERT_EQ(
      Post("/v1/coils", CoilBody("B1", "C2", 1, "2026-03-03T07:00:00Z")).status,
      201);

  HttpResponse r = Get("/v1/rolls/R-F6-top");
  ASSERT_EQ(r.status, 200) << r.body;
  const json life = Parse(r);
  EXPECT_EQ(life["roll_id"], "R-F6-top");
  EXPECT_EQ(life["roll_type"], "ICDP-S3");
  ASSERT_EQ(life["mounts"].size(), 2u) << life.dump();
  const json& m1 = life["mounts"][0];
  EXPECT_EQ(m1["campaign_id"], "C1");
  EXPECT_EQ(m1["stand"], "F6");
  EXPECT_EQ(m1["position"], "top");
  EXPECT_EQ(m1["started_at"], "2026-03-01T06:00:00Z");
  EXPECT_EQ(m1["ended_at"], "2026-03-01T12:00:00Z");
  EXPECT_EQ(m1["coils"], 4);
  EXPECT_NEAR(m1["rolled_length_m"].get<double>(), 4 * 820.5, 1e-9);
  EXPECT_NEAR(m1["rolled_km"].get<double>(), 4 * 0.8205, 1e-12);
  EXPECT_NEAR(m1["predicted_wear_um"].get<double>(),
              end_c1["predicted_wear_um"].get<double>(),
              1e-9 * end_c1["predicted_wear_um"].get<double>());
  EXPECT_EQ(m1["measured_wear_um"], 37.5);
  EXPECT_EQ(m1["diameter_mm"], 700.0);
  EXPECT_EQ(m1["hardness_hb"], 550.0);
  const json& m2 = life["mounts"][1];
  EXPECT_EQ(m2["running"], true);
  EXPECT_EQ(m2["ended_at"], nullptr);
  EXPECT_EQ(m2["coils"], 1);
  EXPECT_EQ(m2["measured_wear_um"], nullptr);
  EXPECT_EQ(m2["predicted_wear_um"],
            Parse(Get("/v1/wear/F6/top"))["predicted_wear_um"]);

  const std::string before = State();
  ExpectRejected(Get("/v1/rolls/NOPE"), 404, "not_found", nullptr, before);
  EXPECT_EQ(Get("/rolls/NOPE").status, 404);
  EXPECT_EQ(Send("POST", "/v1/rolls/R-F6-top", "{}").status, 405);

  const json inv = Parse(Get("/v1/rolls"));
  ASSERT_EQ(inv["rolls"].size(), 4u) << inv.dump();
  json f6top;
  for (const json& roll : inv["rolls"]) {
    if (roll["roll_id"] == "R-F6-top") f6top = roll;
  }
  ASSERT_TRUE(f6top.is_object());
  EXPECT_EQ(f6top["campaigns"], 2);
  EXPECT_NEAR(f6top["total_rolled_km"].get<double>(), 5 * 0.8205, 1e-12);
  EXPECT_EQ(f6top["last_measured_wear_um"], 37.5);
  EXPECT_EQ(f6top["last_diameter_mm"], 700.0);
  EXPECT_EQ(f6top["mounted"], true);
  EXPECT_EQ(f6top["mounted_at"]["stand"], "F6");
  EXPECT_EQ(f6top["mounted_at"]["campaign_id"], "C2");

  // The roll page, linked from the dashboard's mounted-rolls table.
  const HttpResponse page = Get("/rolls/R-F6-top");
  ASSERT_EQ(page.status, 200);
  EXPECT_EQ(page.content_type, "text/html; charset=utf-8");
  EXPECT_NE(page.body.find("data-campaign-id=\"C1\""), std::string::npos);
  EXPECT_NE(page.body.find("data-campaign-id=\"C2\""), std::string::npos);
  EXPECT_NE(page.body.find("<svg"), std::string::npos);
  EXPECT_NE(Get("/").body.find("href=\"/rolls/R-F6-top\""), std::string::npos);
}

TEST_F(ShopRouterTest, FinishedDiagnosesAreServedAfterARestart) {
  ASSERT_NO_FATAL_FAILURE(UseSimulatedMill("diag.db", 60));
  const HttpResponse posted = Post("/v1/diagnoses", json::object());
  ASSERT_EQ(posted.status, 202) << posted.body;
  const int64_t id = Parse(posted)["id"].get<int64_t>();
  const std::string path = "/v1/diagnoses/" + std::to_string(id);
  json report;
  for (int i = 0; i < 3000; ++i) {  // up to 300 s (sanitizer builds are slow)
    report = Parse(Get(path));
    if (report["status"] == "done" || report["status"] == "failed") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(report["status"], "done") << report.dump();

  // Restart: a new store on the same file, new jobs, new router.
  router_.reset();
  diagnoses_.reset();
  store_.reset();
  StatusOr<std::unique_ptr<storage::MillStore>> store = engine::OpenStore(db_);
  ASSERT_TRUE(store.ok());
  store_ = std::move(store).value();
  MakeRouter(ApiOptions());

  HttpResponse r = Get(path);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Parse(r), report);
  const json list = Parse(Get("/v1/diagnoses"));
  ASSERT_EQ(list["diagnoses"].size(), 1u) << list.dump();
  EXPECT_EQ(list["diagnoses"][0]["id"], id);
  EXPECT_EQ(list["diagnoses"][0]["verdict"], report["verdict"]);
  EXPECT_TRUE(list["diagnoses"][0]["finished_at"].is_string());
  r = Get(path + "/report");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/html; charset=utf-8");
  EXPECT_NE(r.body.find("<svg"), std::string::npos);
  const std::string before = State();
  ExpectRejected(Get("/v1/diagnoses/99/report"), 404, "not_found", nullptr,
                 before);
  ExpectRejected(Get("/v1/diagnoses/99"), 404, "not_found", nullptr, before);
  // Ids go on after the stored ones.
  const HttpResponse next = Post("/v1/diagnoses", json::object());
  EXPECT_EQ(Parse(next)["id"], id + 1);
}

}  // namespace
}  // namespace rollwear::api::testing
