// The label rules of GET /metrics (issue 17), checked without promtool:
// the request's real method (DELETE and HEAD are not GET), "unmatched"
// rather than "" for a route no template matched, the exact status code,
// rollwear_build_info with the build's version and commit, the process_*
// figures of /proc/self, and the predicted wear per stand and position.
// Answers go through the real Router over a real SQLite store and are
// recorded as the HTTP server records them (ObserveRequest with the
// answer's labels).
#include <ctime>

#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "api/process_metrics.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

class MetricsLabelsTest : public RouterTest {
 protected:
  // Handles the request and records it as HttpServer::Complete does.
  HttpResponse Observed(const std::string& method, const std::string& path,
                        const std::string& body = "") {
    HttpResponse r = Send(method, path, body);
    router_->metrics()->ObserveRequest(r.route, r.status, 0.0005);
    return r;
  }

  std::string Scrape() {
    const HttpResponse m = Get("/metrics");
    EXPECT_EQ(m.status, 200);
    return m.body;
  }
};

// Every sample line's labels as name -> value.
std::vector<std::map<std::string, std::string>> LabelSets(
    const std::string& exposition, const std::string& metric) {
  std::vector<std::map<std::string, std::string>> out;
  static const std::regex kLabel(R"re(([a-z_]+)="([^"]*)")re");
  std::istringstream in(exposition);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(metric + "{", 0) != 0) continue;
    std::map<std::string, std::string> labels;
    const std::string inside = line.substr(0, line.rfind('}'));
    for (std::sregex_iterator it(inside.begin(), inside.end(), kLabel), end;
         it != end; ++it) {
      labels[(*it)[1]] = (*it)[2];
    }
    out.push_back(labels);
  }
  return out;
}

TEST_F(MetricsLabelsTest, MethodRouteAndExactCodeAreTheRequestsOwn) {
  EXPECT_EQ(Observed("DELETE", "/v1/wear").status, 405);
  EXPECT_EQ(Observed("HEAD", "/v1/wear").status, 200);
  EXPECT_EQ(Observed("GET", "/v1/wear").status, 200);
  EXPECT_EQ(Observed("GET", "/no/such/route").status, 404);
  EXPECT_EQ(Observed("PROPFIND", "/v1/wear").status, 405);
  EXPECT_EQ(
      Observed("POST", "/v1/coils", CoilBody("K1", "C1", 1).dump()).status,
      201);
  EXPECT_EQ(Observed("POST", "/v1/coils", "{").status, 400);
  // Answered before routing (a framing error): no method was read.
  router_->metrics()->ObserveRequest(RouteId::kUnmatched, 431, 0);

  const std::string body = Scrape();
  for (const char* line : {
           "rollwear_http_requests_total{route=\"/v1/wear\",method=\"DELETE\","
           "code=\"405\"} 1",
           "rollwear_http_requests_total{route=\"/v1/wear\",method=\"HEAD\","
           "code=\"200\"} 1",
           "rollwear_http_requests_total{route=\"/v1/wear\",method=\"GET\","
           "code=\"200\"} 1",
           "rollwear_http_requests_total{route=\"unmatched\",method=\"GET\","
           "code=\"404\"} 1",
           "rollwear_http_requests_total{route=\"/v1/wear\",method=\"OTHER\","
           "code=\"405\"} 1",
           "rollwear_http_requests_total{route=\"/v1/coils\",method=\"POST\","
           "code=\"201\"} 1",
           "rollwear_http_requests_total{route=\"/v1/coils\",method=\"POST\","
           "code=\"400\"} 1",
           "rollwear_http_requests_total{route=\"unmatched\",method=\"OTHER\","
           "code=\"431\"} 1",
           "rollwear_http_request_duration_seconds_count{route=\"/v1/wear\","
           "method=\"DELETE\"} 1",
       }) {
    EXPECT_NE(body.find(line), std::string::npos) << line << "\n" << body;
  }
  // The rules, on every sample of both request metrics.
  static const std::set<std::string> kMethods = {
      "GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS", "OTHER"};
  static const std::regex kCode("[1-5][0-9][0-9]");
  int samples = 0;
  for (const char* metric : {"rollwear_http_requests_total",
                             "rollwear_http_request_duration_seconds_count"}) {
    for (const auto& labels : LabelSets(body, metric)) {
      ++samples;
      ASSERT_TRUE(labels.count("route") && labels.count("method")) << metric;
      EXPECT_FALSE(labels.at("route").empty()) << metric;
      EXPECT_EQ(kMethods.count(labels.at("method")), 1u) << labels.at("method");
      if (std::string(metric) == "rollwear_http_requests_total") {
        EXPECT_TRUE(std::regex_match(labels.at("code"), kCode))
            << labels.at("code");
      }
    }
  }
  EXPECT_EQ(samples, 8 + 7);  // 8 (route, method, code), 7 (route, method)
  EXPECT_EQ(body.find("code=\"4xx\""), std::string::npos);
}

TEST_F(MetricsLabelsTest, BuildInfoNamesVersionAndCommit) {
  ApiOptions options;
  options.build = {"9.8.7", "abc1234"};
  MakeRouter(options);
  EXPECT_NE(Scrape().find(
                "rollwear_build_info{version=\"9.8.7\",commit=\"abc1234\"} 1"),
            std::string::npos);
}

TEST_F(MetricsLabelsTest, ProcessFiguresDescribeThisProcess) {
  // Run alone (ctest starts each test in its own process) the binary may
  // not have used a whole clock tick yet: spend 50 ms of CPU first.
  const std::clock_t until = std::clock() + CLOCKS_PER_SEC / 20;
  volatile double sink = 0;
  while (std::clock() < until) sink = sink + 1;
  const ProcessFigures f = ReadProcessFigures();
  ASSERT_TRUE(f.cpu_seconds && f.resident_bytes && f.open_fds &&
              f.start_time_seconds && f.max_fds);
  EXPECT_GT(*f.cpu_seconds, 0);
  // A test binary with a SQLite store: more than 1 MB and less than 4 GB.
  EXPECT_GT(*f.resident_bytes, 1e6);
  EXPECT_LT(*f.resident_bytes, 4e9);
  // stdin, stdout, stderr and the store's database files.
  EXPECT_GE(*f.open_fds, 4);
  EXPECT_LE(*f.open_fds, *f.max_fds);
  // Started before now, and not before this test binary could have been.
  const double now = static_cast<double>(time(nullptr));
  EXPECT_LE(*f.start_time_seconds, now + 1);
  EXPECT_GT(*f.start_time_seconds, now - 3 * 3600);
  const std::string body = Scrape();
  for (const char* name :
       {"\nprocess_cpu_seconds_total ", "\nprocess_resident_memory_bytes ",
        "\nprocess_open_fds ", "\nprocess_start_time_seconds ",
        "# TYPE process_cpu_seconds_total counter"}) {
    EXPECT_NE(body.find(name), std::string::npos) << name;
  }
}

TEST_F(MetricsLabelsTest, PredictedWearGaugePerStandAndPosition) {
  ASSERT_EQ(Post("/v1/coils", CoilBody("K1", "C1", 1)).status, 201);
  const json wear = Parse(Get("/v1/wear"));
  ASSERT_EQ(wear["positions"].size(), 4u) << wear.dump();
  const std::string body = Scrape();
  const auto gauges = LabelSets(body, "rollwear_predicted_wear_um");
  ASSERT_EQ(gauges.size(), 4u) << body;
  for (const json& p : wear["positions"]) {
    const std::string labels =
        "rollwear_predicted_wear_um{stand=\"" + p["stand"].get<std::string>() +
        "\",position=\"" + p["position"].get<std::string>() + "\"} ";
    const size_t at = body.find(labels);
    ASSERT_NE(at, std::string::npos) << labels << body;
    const double value = std::stod(body.substr(at + labels.size()));
    const double expected = p["predicted_wear_um"].get<double>();
    EXPECT_GT(expected, 0);
    EXPECT_NEAR(value, expected, 1e-9 * expected) << labels;
  }
}

}  // namespace
}  // namespace rollwear::api::testing
