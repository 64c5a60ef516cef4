// Test fixture of api_test: a Router over the real MillStore on a fresh
// SQLite file in a temporary folder, with the daemon's diagnosis jobs
// (engine/diagnosis_jobs.h with the daemon's hooks,
// service/jobs/diagnosis_hooks.h) and one open campaign (C1, rolls at
// F6/F7 top and bottom), and helpers that build valid request bodies and
// check error answers.
//
// Thread-safety: one fixture per test.
#ifndef ROLLWEAR_TESTS_API_API_TEST_UTIL_H_
#define ROLLWEAR_TESTS_API_API_TEST_UTIL_H_

#include <stdlib.h>

#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "api/router.h"
#include "engine/calibration_runs.h"
#include "engine/diagnosis_jobs.h"
#include "engine/wear_prediction.h"
#include "service/jobs/diagnosis_hooks.h"
#include "storage/mill_store.h"

namespace rollwear::api::testing {

using json = nlohmann::json;

inline json RollChangeBody(const std::string& campaign_id,
                           const std::string& started_at,
                           const std::string& roll_suffix = "") {
  json rolls = json::array();
  for (const char* stand : {"F6", "F7"}) {
    for (const char* position : {"top", "bottom"}) {
      rolls.push_back({{"stand", stand},
                       {"position", position},
                       {"roll_id", std::string("R-") + stand + "-" + position +
                                       roll_suffix},
                       {"roll_type", "ICDP-S3"},
                       {"diameter_mm", 700.0},
                       {"hardness_hb", 550.0}});
    }
  }
  return {{"campaign_id", campaign_id},
          {"started_at", started_at},
          {"rolls", rolls}};
}

inline json PassBody(const std::string& stand, double force_kn) {
  return {{"stand", stand},
          {"force_kn", force_kn},
          {"width_mm", 1250.0},
          {"length_m", 820.5},
          {"entry_thickness_mm", 4.2},
          {"exit_thickness_mm", 3.4},
          {"temperature_c", 905.0},
          {"speed_mps", 9.5},
          {"lubrication", 1},
          {"shift_mm", -35.0}};
}

inline json CoilBody(const std::string& coil_id, const std::string& campaign_id,
                     int seq, const std::string& rolled_at = "") {
  const std::string at =
      rolled_at.empty() ? "2026-03-01T07:" + std::string(seq < 10 ? "0" : "") +
                              std::to_string(seq % 60) + ":00Z"
                        : rolled_at;
  return {{"coil_id", coil_id},
          {"campaign_id", campaign_id},
          {"seq", seq},
          {"rolled_at", at},
          {"grade", "DP600"},
          {"passes",
           json::array({PassBody("F6", 21000.0), PassBody("F7", 17500.0)})}};
}

inline json MeasurementBody(const std::string& campaign_id,
                            const std::string& stand,
                            const std::string& position,
                            const std::string& roll_id, double wear_um) {
  return {{"campaign_id", campaign_id},
          {"stand", stand},
          {"position", position},
          {"roll_id", roll_id},
          {"measured_at", "2026-03-02T10:00:00Z"},
          {"wear_center_um", wear_um}};
}

class RouterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/rollwear_api_test_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
    StatusOr<std::unique_ptr<storage::MillStore>> store =
        engine::OpenStore(dir_ + "/api.db");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(store).value();
    MakeRouter(ApiOptions());
    const HttpResponse r =
        Post("/v1/roll-changes", RollChangeBody("C1", "2026-03-01T06:00:00Z"));
    ASSERT_EQ(r.status, 201) << r.body;
  }

  void TearDown() override {
    router_.reset();
    diagnoses_.reset();
    runs_.reset();
    store_.reset();
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  // A router over store_ with fresh diagnosis jobs (unless `options`
  // brings its own runner).
  void MakeRouter(ApiOptions options) {
    router_.reset();
    diagnoses_.reset();
    runs_ = std::make_unique<engine::CalibrationRuns>(store_.get());
    diagnoses_ = std::make_unique<engine::DiagnosisJobs>(
        store_.get(), runs_.get(), service::DaemonDiagnosisHooks());
    if (options.diagnoses == nullptr) options.diagnoses = diagnoses_.get();
    router_ = std::make_unique<Router>(store_.get(), std::move(options));
  }

  HttpResponse Send(const std::string& method, const std::string& path,
                    const std::string& body,
                    const std::string& authorization = "") {
    HttpRequest request;
    request.method = method;
    request.path = path;
    request.body = body;
    if (!authorization.empty()) {
      request.headers.emplace_back("Authorization", authorization);
    }
    return router_->Handle(request);
  }
  HttpResponse Post(const std::string& path, const json& body,
                    const std::string& authorization = "") {
    return Send("POST", path, body.dump(), authorization);
  }
  HttpResponse PostRaw(const std::string& path, const std::string& body,
                       const std::string& authorization = "") {
    return Send("POST", path, body, authorization);
  }
  HttpResponse Get(const std::string& path) { return Send("GET", path, ""); }

  // GET /v1/wear plus the store's counters: what a rejected request must
  // leave as it was.
  std::string State() {
    const HttpResponse wear = Get("/v1/wear");
    const storage::StoreCounters c = store_->Counters();
    return wear.body + "|" + std::to_string(c.coils) + "," +
           std::to_string(c.campaigns) + "," + std::to_string(c.measurements);
  }

  // Checks status, error code and field of an error answer, the error
  // body's shape, and that the state is unchanged since `before`.
  void ExpectRejected(const HttpResponse& r, int status,
                      const std::string& code, const json& field,
                      const std::string& before) {
    EXPECT_EQ(r.status, status) << r.body;
    const json body = json::parse(r.body, nullptr, false);
    ASSERT_TRUE(body.is_object()) << r.body;
    ASSERT_TRUE(body.contains("error")) << r.body;
    const json& e = body["error"];
    EXPECT_EQ(e.value("code", ""), code) << r.body;
    EXPECT_TRUE(e.contains("message") && e["message"].is_string() &&
                !e["message"].get<std::string>().empty())
        << r.body;
    ASSERT_TRUE(e.contains("field")) << r.body;
    EXPECT_EQ(e["field"], field) << r.body;
    EXPECT_EQ(State(), before) << "a rejected request changed the state";
  }

  static json Parse(const HttpResponse& r) {
    return json::parse(r.body, nullptr, false);
  }

  std::string dir_;
  std::unique_ptr<storage::MillStore> store_;
  std::unique_ptr<engine::CalibrationRuns> runs_;
  std::unique_ptr<engine::DiagnosisJobs> diagnoses_;
  std::unique_ptr<Router> router_;
};

}  // namespace rollwear::api::testing

#endif  // ROLLWEAR_TESTS_API_API_TEST_UTIL_H_
