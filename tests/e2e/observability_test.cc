// End-to-end tests of what the daemon tells its operator (issue 17), on the
// real `rollwear serve`: every model promotion and every diagnosis job is
// logged in the key=value event format of service/jobs/job_log.h, every
// calibration run is counted (the diagnosis adoption's too), the request
// metrics carry the real method and exact code through the real HTTP
// server, rollwear_build_info matches `rollwear --version`, and the whole
// exposition passes `promtool check metrics` (skipped without promtool,
// unless ROLLWEAR_REQUIRE_EDGE=1).
#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "api/http_client.h"
#include "tests/e2e/edge_util.h"

namespace rollwear::e2e {
namespace {

// GET until "status" is done or failed (up to 300 s).
json WaitDone(const std::string& url, const std::string& path) {
  json body;
  for (int i = 0; i < 3000; ++i) {
    if (HttpGet(url, path, &body) == 200 &&
        (body["status"] == "done" || body["status"] == "failed")) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return body;
}

std::string RawMetrics(const std::string& url) {
  api::HttpClient client(url);
  return client.Get("/metrics").body;
}

// Lines of `log` that contain `needle`.
std::vector<std::string> LinesWith(const std::string& log,
                                   const std::string& needle) {
  std::vector<std::string> out;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) {
    if (line.find(needle) != std::string::npos) out.push_back(line);
  }
  return out;
}

// Requests a scraper sees besides the API's own: other methods, unknown
// routes, errors.
void SendOddRequests(const std::string& url) {
  api::HttpClient client(url);
  EXPECT_EQ(client.Send("DELETE", "/v1/wear", "", "").status, 405);
  EXPECT_EQ(client.Send("PUT", "/v1/coils", "{}", "application/json").status,
            405);
  EXPECT_EQ(client.Get("/no/such/route").status, 404);
  EXPECT_EQ(client.Post("/v1/coils", "{").status, 400);
}

TEST(ObservabilityTest, PromotionsAndDiagnosesAreLoggedAndEveryRunCounted) {
  TempDir dir;
  std::string output;
  ASSERT_EQ(RunRollwear({"simulate", "--out", dir / "data", "--seed", "33",
                         "--campaigns", "240", "--effect", "lubrication"},
                        &output),
            0)
      << output;
  ASSERT_EQ(RunRollwear({"import", "--db", dir / "rollwear.db", dir / "data"},
                        &output),
            0)
      << output;
  Daemon daemon(dir / "rollwear.db", dir / "serve.log");
  std::string error;
  ASSERT_TRUE(daemon.Start(&error)) << error;

  // The adoption of a diagnosis: against the prior model it is promoted.
  json answer;
  ASSERT_EQ(
      HttpPost(daemon.url(), "/v1/diagnoses", "{\"adopt\": true}", &answer),
      202);
  const json diagnosis = WaitDone(daemon.url(), "/v1/diagnoses/1");
  ASSERT_EQ(diagnosis["status"], "done") << diagnosis.dump().substr(0, 2000);
  ASSERT_TRUE(diagnosis.contains("adoption")) << diagnosis.dump();
  ASSERT_TRUE(diagnosis["adoption"]["promoted"].get<bool>());
  const int64_t adoption_run = diagnosis["adoption"]["calibration_id"];
  // Then a calibration through the API (promoted or not, as it scores).
  ASSERT_EQ(HttpPost(daemon.url(), "/v1/calibrations", "{}", &answer), 202);
  const int64_t api_run = answer["id"];
  const json calibration =
      WaitDone(daemon.url(), "/v1/calibrations/" + std::to_string(api_run));
  ASSERT_EQ(calibration["status"], "done") << calibration.dump();
  const bool api_promoted = calibration["promoted"].get<bool>();

  // The run's log line and metrics come from the scheduler's callback,
  // after the run is stored as done: wait for them (up to 10 s) rather than
  // race them (ctest -j2 once read the log first).
  const std::string api_finished =
      "event=calibration_finished id=" + std::to_string(api_run) + " trigger=api";
  for (int i = 0; i < 100 && LinesWith(ReadFile(dir / "serve.log"), api_finished)
                                 .empty();
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::string log = ReadFile(dir / "serve.log");
  EXPECT_EQ(LinesWith(log, "event=diagnosis_started id=1 adopt=true").size(),
            1u)
      << log;
  const std::regex finished(
      "event=diagnosis_finished id=1 adopt=true status=done "
      "verdict=missing_physics_found seconds=[0-9]+\\.[0-9] "
      "adoption_calibration_id=" +
      std::to_string(adoption_run) + " promoted=true");
  EXPECT_TRUE(std::regex_search(log, finished)) << log;
  const std::vector<std::string> promotions =
      LinesWith(log, "event=model_promoted ");
  ASSERT_EQ(promotions.size(), api_promoted ? 2u : 1u) << log;
  EXPECT_NE(promotions[0].find("event=model_promoted version=1 "
                               "source=diagnosis trigger=\"diagnosis 1\" "
                               "calibration_id=" +
                               std::to_string(adoption_run)),
            std::string::npos)
      << promotions[0];
  if (api_promoted) {
    EXPECT_NE(promotions[1].find("event=model_promoted version=2 "
                                 "source=calibration trigger=api"),
              std::string::npos)
        << promotions[1];
  }
  EXPECT_EQ(LinesWith(log, "event=calibration_finished id=" +
                               std::to_string(api_run) + " trigger=api")
                .size(),
            1u)
      << log;
  // Both runs counted: the adoption's and the API's.
  const std::string metrics = RawMetrics(daemon.url());
  EXPECT_NE(metrics.find("rollwear_calibration_runs_total{status=\"done\"} 2"),
            std::string::npos)
      << metrics;
  EXPECT_NE(metrics.find("rollwear_calibration_duration_seconds_count 2"),
            std::string::npos)
      << metrics;
}

TEST(ObservabilityTest, RequestLabelsAndBuildInfoThroughTheRealServer) {
  TempDir dir;
  std::string error, version;
  ASSERT_TRUE(Simulate(dir / "data", 4, 7, &error)) << error;
  ASSERT_EQ(RunRollwear({"--version"}, &version), 0) << version;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      version, m, std::regex(R"(rollwear (\S+) \(commit (\S+)\))")))
      << version;
  Daemon daemon(dir / "rollwear.db", dir / "serve.log");
  ASSERT_TRUE(daemon.Start(&error)) << error;
  std::string output;
  ASSERT_EQ(RunRollwear({"replay", "--data", dir / "data", "--url",
                         daemon.url(), "--leave-last-open", "--quiet"},
                        &output),
            0)
      << output;
  SendOddRequests(daemon.url());
  api::HttpClient client(daemon.url());
  EXPECT_EQ(client.Send("HEAD", "/v1/wear", "", "").status, 200);

  const std::string metrics = RawMetrics(daemon.url());
  for (const std::string& line : {
           std::string("rollwear_build_info{version=\"") + m[1].str() +
               "\",commit=\"" + m[2].str() + "\"} 1",
           std::string("rollwear_http_requests_total{route=\"/v1/wear\","
                       "method=\"DELETE\",code=\"405\"} 1"),
           std::string("rollwear_http_requests_total{route=\"/v1/wear\","
                       "method=\"HEAD\",code=\"200\"} 1"),
           std::string("rollwear_http_requests_total{route=\"/v1/coils\","
                       "method=\"PUT\",code=\"405\"} 1"),
           std::string("rollwear_http_requests_total{route=\"unmatched\","
                       "method=\"GET\",code=\"404\"} 1"),
           std::string("rollwear_http_requests_total{route=\"/v1/coils\","
                       "method=\"POST\",code=\"400\"} 1"),
       }) {
    EXPECT_NE(metrics.find(line), std::string::npos) << line << "\n" << metrics;
  }
  EXPECT_EQ(metrics.find("route=\"\""), std::string::npos);
  EXPECT_EQ(metrics.find("method=\"\""), std::string::npos);
  EXPECT_EQ(LinesWith(metrics, "rollwear_predicted_wear_um{").size(), 4u)
      << metrics;
  EXPECT_NE(metrics.find("\nprocess_resident_memory_bytes "),
            std::string::npos);

  std::string message;
  if (!EdgeToolPresent("/usr/bin/promtool", &message)) {
    if (!message.empty()) FAIL() << message;
    GTEST_SKIP() << "promtool is not installed (apt-get install prometheus)";
  }
  std::ofstream(dir / "metrics.txt") << metrics;
  Subprocess promtool(
      {"/bin/sh", "-c",
       "/usr/bin/promtool check metrics < '" + (dir / "metrics.txt") + "'"},
      dir / "promtool.log");
  EXPECT_EQ(promtool.Wait(60), 0) << ReadFile(dir / "promtool.log");
  EXPECT_EQ(ReadFile(dir / "promtool.log"), "");
}

}  // namespace
}  // namespace rollwear::e2e
