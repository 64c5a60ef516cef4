// POST /v1/diagnoses and GET /v1/diagnoses/{id} over the real store: the
// daemon runs the same diagnosis as `rollwear diagnose` on everything it
// holds and answers with the same JSON.
#include <chrono>
#include <thread>

#include "core/simulator.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

TEST_F(RouterTest, DiagnosisRunsOnStoredDataAndNamesTheConcealedEffect) {
  // A fresh store holding a simulated mill with a concealed lubrication
  // effect (the fixture's own open campaign lives in another store).
  router_.reset();
  store_.reset();
  StatusOr<std::unique_ptr<storage::MillStore>> store =
      storage::MillStore::Open(dir_ + "/diag.db", storage::StoreOptions());
  ASSERT_TRUE(store.ok());
  store_ = std::move(store).value();
  SimulatorOptions so;
  so.seed = 31;
  so.num_campaigns = 240;
  so.effects = {"lubrication"};
  StatusOr<Simulation> sim = Simulate(so);
  ASSERT_TRUE(sim.ok());
  ASSERT_TRUE(store_->ImportDataset(sim->data).ok());
  MakeRouter(ApiOptions());

  const HttpResponse posted = Post("/v1/diagnoses", json::object());
  ASSERT_EQ(posted.status, 202) << posted.body;
  const int64_t id = Parse(posted)["id"].get<int64_t>();
  json report;
  for (int i = 0; i < 600; ++i) {
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
  EXPECT_LT(report["findings"][0]["gap_val_after_um"].get<double>(),
            report["findings"][0]["gap_val_before_um"].get<double>());
  EXPECT_TRUE(report["baseline"].contains("gap_val_um"));
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
