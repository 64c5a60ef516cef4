// End-to-end test of nginx as the edge (deploy/nginx/rollwear.conf, issue
// 17): a real nginx in the foreground in front of the real `rollwear serve`
// on a temporary SQLite file. A small simulated dataset replayed through
// nginx gives the same wear as the daemon serves directly; the daemon's
// error answers (400, 401, 404, 409, 422) pass through nginx unchanged,
// and nginx's own 413 for a body over the limit is the daemon's 413; the
// shipped TLS configuration passes `nginx -t` with a self-signed
// certificate and serves HTTPS with it (curl). Skipped when nginx is not
// installed, unless ROLLWEAR_REQUIRE_EDGE=1 (the CI phase "edge").
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "api/http_client.h"
#include "api/request_encode.h"
#include "core/dataset/dataset_io.h"
#include "tests/e2e/edge_util.h"

#ifndef ROLLWEAR_SOURCE_DIR
#error "ROLLWEAR_SOURCE_DIR must name the source tree"
#endif

namespace rollwear::e2e {
namespace {

constexpr char kNginx[] = "/usr/sbin/nginx";
constexpr char kToken[] = "edge-test-token";

std::string ShippedConfig() {
  return ReadFile(std::string(ROLLWEAR_SOURCE_DIR) +
                  "/deploy/nginx/rollwear.conf");
}

struct Answer {
  int status = 0;
  std::string body;
};

Answer Send(const std::string& url, const std::string& method,
            const std::string& path, const std::string& body,
            const std::string& token) {
  api::HttpClientOptions options;
  options.token = token;
  api::HttpClient client(url, options);
  const api::HttpResult r =
      client.Send(method, path, body, body.empty() ? "" : "application/json");
  return {r.status, r.answered() ? r.body : "no answer: " + r.error};
}

class NginxTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string message;
    if (!EdgeToolPresent(kNginx, &message)) {
      if (!message.empty()) FAIL() << message;
      GTEST_SKIP() << kNginx << " is not installed (apt-get install nginx)";
    }
    std::string error;
    ASSERT_TRUE(Simulate(dir_ / "data", 6, 11, &error)) << error;
    StatusOr<Dataset> data = ReadDataset(dir_ / "data");
    ASSERT_TRUE(data.ok()) << data.status().ToString();
    data_ = std::move(data).value();
    daemon_ = std::make_unique<Daemon>(
        dir_ / "rollwear.db", dir_ / "serve.log", 0, std::vector<std::string>{},
        std::vector<std::string>{std::string("ROLLWEAR_TOKEN=") + kToken});
    ASSERT_TRUE(daemon_->Start(&error)) << error;
    port_ = FreeLoopbackPort();
    redirect_port_ = FreeLoopbackPort();
    ASSERT_GT(port_, 0);
    const std::string site =
        DeriveEdgeConfig(ShippedConfig(), daemon_->port(), port_,
                         redirect_port_, "", "", &error);
    ASSERT_FALSE(site.empty()) << error;
    nginx_ = std::make_unique<EdgeNginx>(dir_.path(), site);
    ASSERT_TRUE(nginx_->Start(port_, &error)) << error;
  }

  std::string edge_url() const {
    return "http://127.0.0.1:" + std::to_string(port_);
  }

  // The same request directly and through nginx: both answers equal, with
  // `status`.
  void ExpectPassedThrough(const std::string& method, const std::string& path,
                           const std::string& body, const std::string& token,
                           int status) {
    const Answer direct = Send(daemon_->url(), method, path, body, token);
    const Answer edge = Send(edge_url(), method, path, body, token);
    EXPECT_EQ(direct.status, status)
        << method << " " << path << " " << direct.body;
    EXPECT_EQ(edge.status, direct.status) << method << " " << path;
    EXPECT_EQ(edge.body, direct.body) << method << " " << path;
    EXPECT_NE(direct.body.find("\"error\""), std::string::npos) << direct.body;
  }

  TempDir dir_;
  Dataset data_;
  std::unique_ptr<Daemon> daemon_;
  int port_ = 0, redirect_port_ = 0;
  // Declared last: nginx goes before the daemon and the folder.
  std::unique_ptr<EdgeNginx> nginx_;
};

TEST_F(NginxTest, ReplayThroughNginxServesTheDirectWear) {
  std::string output;
  const int code = RunRollwear(
      {"replay", "--data", dir_ / "data", "--url", edge_url(), "--token",
       kToken, "--clients", "8", "--leave-last-open", "--quiet"},
      &output, 300);
  ASSERT_EQ(code, 0) << output << nginx_->ErrorLog();
  EXPECT_NE(output.find(" 0 conflicts, 0 errors"), std::string::npos) << output;
  json direct, edge;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &direct), 200);
  ASSERT_EQ(HttpGet(edge_url(), "/v1/wear", &edge), 200);
  ASSERT_EQ(direct["positions"].size(), 4u) << direct.dump();
  EXPECT_EQ(edge, direct);
  const auto metrics = ScrapeMetrics(daemon_->url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"),
            static_cast<double>(data_.coil_ids.size()));
  // Plain HTTP on the redirect server is sent to HTTPS.
  const Answer redirect =
      Send("http://127.0.0.1:" + std::to_string(redirect_port_), "GET",
           "/v1/wear", "", "");
  EXPECT_EQ(redirect.status, 301) << redirect.body;
}

TEST_F(NginxTest, ErrorAnswersPassThroughUnchanged) {
  // Campaign 0 with its coils, ended; campaign 1 started.
  ASSERT_EQ(HttpPost(daemon_->url(), "/v1/roll-changes",
                     RollChangeJson(data_, 0).dump(), nullptr, kToken),
            201);
  const std::vector<int> coils = CoilsOf(data_, 0);
  ASSERT_GE(coils.size(), 2u);
  const json first = CoilJson(data_, coils[0]);
  ASSERT_EQ(
      HttpPost(daemon_->url(), "/v1/coils", first.dump(), nullptr, kToken),
      201);
  const std::string campaign = data_.campaigns[0].id;
  ASSERT_EQ(HttpPost(daemon_->url(), "/v1/campaigns/" + campaign + "/end",
                     api::CampaignEndRequest(data_, 0), nullptr, kToken),
            200);

  ExpectPassedThrough("POST", "/v1/coils", "{\"coil_id\": ", kToken, 400);
  ExpectPassedThrough("POST", "/v1/coils", first.dump(), "", 401);
  ExpectPassedThrough("GET", "/v1/no-such-thing", "", "", 404);
  json changed = first;
  changed["grade"] = first["grade"].get<std::string>() + "-other";
  ExpectPassedThrough("POST", "/v1/coils", changed.dump(), kToken, 409);
  json late = CoilJson(data_, coils[1]);
  ExpectPassedThrough("POST", "/v1/coils", late.dump(), kToken, 422);

  // Over the body limit nginx answers itself, with the daemon's 413.
  const std::string big(1048577, ' ');
  const Answer direct = Send(daemon_->url(), "POST", "/v1/coils", big, kToken);
  const Answer edge = Send(edge_url(), "POST", "/v1/coils", big, kToken);
  EXPECT_EQ(edge.status, 413) << edge.body;
  if (direct.status != 0) {  // the daemon may close before reading it all
    EXPECT_EQ(direct.status, 413) << direct.body;
    EXPECT_EQ(edge.body, direct.body);
  }
  EXPECT_NE(edge.body.find("\"payload_too_large\""), std::string::npos)
      << edge.body;
  // Nothing refused was stored.
  const auto metrics = ScrapeMetrics(daemon_->url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"), 1);
}

TEST(NginxTlsTest, ShippedTlsConfigPassesNginxTAndServesHttps) {
  std::string message;
  for (const char* tool : {kNginx, "/usr/bin/openssl", "/usr/bin/curl"}) {
    if (!EdgeToolPresent(tool, &message)) {
      if (!message.empty()) FAIL() << message;
      GTEST_SKIP() << tool << " is not installed";
    }
  }
  TempDir dir;
  Subprocess openssl(
      {"/usr/bin/openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes",
       "-keyout", dir / "rollwear.key", "-out", dir / "rollwear.crt", "-days",
       "2", "-subj", "/CN=rollwear.mill.example", "-addext",
       "subjectAltName=DNS:rollwear.mill.example"},
      dir / "openssl.log");
  ASSERT_EQ(openssl.Wait(120), 0) << ReadFile(dir / "openssl.log");
  Daemon daemon(dir / "rollwear.db", dir / "serve.log");
  std::string error;
  ASSERT_TRUE(daemon.Start(&error)) << error;
  const int port = FreeLoopbackPort();
  const std::string site =
      DeriveEdgeConfig(ShippedConfig(), daemon.port(), port, FreeLoopbackPort(),
                       dir / "rollwear.crt", dir / "rollwear.key", &error);
  ASSERT_FALSE(site.empty()) << error;
  EXPECT_NE(site.find(" ssl;"), std::string::npos);
  EdgeNginx nginx(dir.path(), site);
  std::string output;
  EXPECT_EQ(nginx.Test(&output), 0) << output;
  EXPECT_NE(output.find("test is successful"), std::string::npos) << output;

  // HTTPS with the certificate verified against its own name.
  ASSERT_TRUE(nginx.Start(port, &error)) << error;
  const std::string host = "rollwear.mill.example:" + std::to_string(port);
  Subprocess curl({"/usr/bin/curl", "-sS", "--cacert", dir / "rollwear.crt",
                   "--resolve", host + ":127.0.0.1", "-w", " HTTP=%{http_code}",
                   "https://" + host + "/healthz"},
                  dir / "curl.log");
  ASSERT_EQ(curl.Wait(60), 0) << ReadFile(dir / "curl.log");
  const std::string answer = ReadFile(dir / "curl.log");
  EXPECT_NE(answer.find("\"status\":\"ok\""), std::string::npos) << answer;
  EXPECT_NE(answer.find(" HTTP=200"), std::string::npos) << answer;
}

}  // namespace
}  // namespace rollwear::e2e
