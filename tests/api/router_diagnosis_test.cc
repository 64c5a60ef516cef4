// POST /v1/diagnoses and GET /v1/diagnoses/{id} over the real store: the
// daemon runs the same diagnosis as `rollwear diagnose` on everything it
// holds and answers with the same JSON.
#include <chrono>
#include <optional>
#include <thread>

#include "core/sim/simulator.h"
#include "engine/wear_prediction.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

// Replaces the fixture's store by a fresh one at `db` holding a simulated
// mill (240 campaigns) with a concealed lubrication effect; with a
// `gauge_fault`, its 8th measurement reads that instead.
class DiagnosisRouterTest : public RouterTest {
 public:
  void UseSimulatedMill(const std::string& db, uint64_t seed,
                        std::optional<double> gauge_fault = std::nullopt) {
    router_.reset();
    store_.reset();
    StatusOr<std::unique_ptr<storage::MillStore>> store =
        engine::OpenStore(dir_ + "/" + db);
    ASSERT_TRUE(store.ok());
    store_ = std::move(store).value();
    SimulatorOptions so;
    so.seed = seed;
    so.num_campaigns = 240;
    so.effects = {"lubrication"};
    StatusOr<Simulation> sim = Simulate(so);
    ASSERT_TRUE(sim.ok());
    if (gauge_fault) sim->data.measurements[7].wear_center_um = *gauge_fault;
    ASSERT_TRUE(store_->ImportDataset(sim->data).ok());
    MakeRouter(ApiOptions());
  }
};

TEST_F(DiagnosisRouterTest,
       DiagnosisRunsOnStoredDataAndNamesTheConcealedEffect) {
  // A fresh store holding a simulated mill with a concealed lubrication
  // effect (the fixture's own open campaign lives in another store), and
  // one gauge fault, stored flagged and left out.
  ASSERT_NO_FATAL_FAILURE(UseSimulatedMill("diag.db", 31, -62.6));

  const HttpResponse posted = Post("/v1/diagnoses", json::object());
  ASSERT_EQ(posted.status, 202) << posted.body;
  const int64_t id = Parse(posted)["id"].get<int64_t>();
  json report;
  for (int i = 0; i < 3000; ++i) {  // up to 300 s (sanitizer builds are slow)
    const HttpResponse r = Get("/v1/diagnoses/" + std::to_string(id));
    ASSERT_EQ(r.status, 200) << r.body;
    report = Parse(r);
    if (report["status"] == "done" || report["status"] == "failed") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(report["status"], "done") << report.dump();
  EXPECT_EQ(report["id"], id);
  EXPECT_EQ(report["verdict"], "missing_physics_found");
  ASSERT_GE(report["findings"].size(), 1u);
  EXPECT_EQ(report["findings"][0]["covariate"], "lubrication");
  EXPECT_EQ(report["findings"][0]["mechanism"], "roll_gap_lubrication");
  // A global finding: scope null, no levels (api.md).
  EXPECT_TRUE(report["findings"][0]["scope"].is_null()) << report["findings"][0].dump();
  EXPECT_EQ(report["findings"][0]["levels"], json::array());
  EXPECT_EQ(report["findings"][0]["scope_undetermined"], json::array());
  EXPECT_TRUE(report["unexplained"].is_array());
  EXPECT_TRUE(report["runners_up"].is_array());
  EXPECT_LT(report["findings"][0]["gap_val_after_um"].get<double>(),
            report["findings"][0]["gap_val_before_um"].get<double>());
  EXPECT_TRUE(report["baseline"].contains("gap_val_um"));
  const json& quality = report["data_quality"];
  EXPECT_EQ(quality["suspect_measurements"], 1) << quality.dump();
  EXPECT_EQ(quality["counts"]["negative_wear"], 1);
  ASSERT_EQ(quality["issues"].size(), 1u);
  EXPECT_EQ(quality["issues"][0]["value_um"], -62.6);
}

TEST_F(DiagnosisRouterTest,
       DiagnosisWithAdoptPromotesTheAdoptedModelWithItsTerms) {
  ASSERT_NO_FATAL_FAILURE(UseSimulatedMill("adopt.db", 33));

  const HttpResponse posted = Post("/v1/diagnoses", json{{"adopt", true}});
  ASSERT_EQ(posted.status, 202) << posted.body;
  const int64_t id = Parse(posted)["id"].get<int64_t>();
  json report;
  for (int i = 0; i < 3000; ++i) {  // up to 300 s (sanitizer builds are slow)
    report = Parse(Get("/v1/diagnoses/" + std::to_string(id)));
    if (report["status"] == "done" || report["status"] == "failed") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(report["status"], "done") << report.dump();
  ASSERT_TRUE(report.contains("adoption")) << report.dump();
  const json& adoption = report["adoption"];
  // The prior (uncalibrated) model is active: the adopted model beats it.
  EXPECT_TRUE(adoption["promoted"].get<bool>()) << adoption.dump();
  EXPECT_LT(adoption["gap_val_um"].get<double>(),
            adoption["active_gap_val_um"].get<double>());
  const int64_t run = adoption["calibration_id"].get<int64_t>();
  const json calibration =
      Parse(Get("/v1/calibrations/" + std::to_string(run)));
  EXPECT_EQ(calibration["trigger"], "diagnosis " + std::to_string(id));
  EXPECT_EQ(calibration["status"], "done");
  const json active = Parse(Get("/v1/models/active"));
  EXPECT_EQ(active["version"], adoption["model_version"]);
  EXPECT_EQ(active["model"], "wang");
  ASSERT_EQ(active["terms"].size(), report["findings"].size()) << active.dump();
  EXPECT_EQ(active["terms"][0]["covariate"],
            report["findings"][0]["covariate"]);
  EXPECT_EQ(active["terms"][0]["params"].size(),
            report["findings"][0]["term"]["params"].size());
}

TEST_F(RouterTest, DiagnosisAndCalibrationRequestsAreValidated) {
  HttpResponse r = Post("/v1/diagnoses", json{{"adopt", "yes"}});
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(Parse(r)["error"]["field"], "adopt");
  r = Post("/v1/calibrations", json{{"model", "lstm"}});
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_NE(Parse(r)["error"]["message"].get<std::string>().find("ann"),
            std::string::npos);
  r = Post("/v1/calibrations", json{{"model", "ann"}});
  ASSERT_EQ(r.status, 202) << r.body;
  const json rec = Parse(
      Get("/v1/calibrations/" + std::to_string(Parse(r)["id"].get<int64_t>())));
  EXPECT_EQ(rec["model"], "ann");
  EXPECT_EQ(rec["status"], "queued");
}

TEST_F(RouterTest, UnknownDiagnosisIs404AndPostNeedsTheToken) {
  EXPECT_EQ(Get("/v1/diagnoses/999").status, 404);
  EXPECT_EQ(Get("/v1/diagnoses/abc").status, 404);
  ApiOptions options;
  options.token = "secret-token";
  MakeRouter(options);
  EXPECT_EQ(Post("/v1/diagnoses", json::object()).status, 401);
}

}  // namespace
}  // namespace rollwear::api::testing
