// The HTTP server's security limits over a real loopback socket: the
// default bind address, the bearer token on writes (and not on reads), the
// body limit (413 before the body is read), the header count/size limits
// (431) and the JSON nesting limit, each answered with the error body of
// the API contract and changing nothing.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include <gtest/gtest.h>

#include "api/http_client.h"
#include "api/http_server.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

constexpr const char* kToken = "s3cret-token";

// Sends raw bytes on a fresh connection and returns what comes back until
// the server closes it or 5 s pass.
std::string RawExchange(int port, const std::string& request) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return "";
  timeval tv{5, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string answer;
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0) {
    size_t sent = 0;
    while (sent < request.size()) {
      const ssize_t n =
          send(fd, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += static_cast<size_t>(n);
    }
    char buf[4096];
    ssize_t n;
    while ((n = recv(fd, buf, sizeof(buf), 0)) > 0) {
      answer.append(buf, static_cast<size_t>(n));
      if (answer.find("\r\n\r\n") != std::string::npos &&
          answer.find("}}") != std::string::npos) {
        break;  // the whole (small) error body is in
      }
    }
  }
  close(fd);
  return answer;
}

class HttpLimitsTest : public RouterTest {
 protected:
  void SetUp() override {
    RouterTest::SetUp();
    ApiOptions options;
    options.token = kToken;
    options.body_limit_bytes = 4096;
    MakeRouter(options);
    HttpServerOptions http;
    http.payload_max_bytes = 4096;
    server_ = std::make_unique<HttpServer>(router_.get(), http);
    ASSERT_TRUE(server_->Start().ok());
    url_ = "http://127.0.0.1:" + std::to_string(server_->port());
  }
  void TearDown() override {
    server_.reset();
    RouterTest::TearDown();
  }

  HttpResult PostWith(const std::string& path, const std::string& body,
                      const std::string& authorization) {
    HttpClient client(url_);
    return client.Send("POST", path, body, "application/json",
                       authorization.empty() ? "" : "Authorization",
                       authorization);
  }
  static std::string ErrorCode(const std::string& body) {
    const json j = json::parse(body, nullptr, false);
    if (!j.is_object() || !j.contains("error")) return "<no error body>";
    return j["error"].value("code", "");
  }

  std::unique_ptr<HttpServer> server_;
  std::string url_;
};

TEST(HttpServerDefaultsTest, BindsLoopbackByDefault) {
  EXPECT_EQ(HttpServerOptions().bind_address, "127.0.0.1");
  EXPECT_FALSE(HttpServerOptions().bind_address.empty());
}

TEST_F(HttpLimitsTest, WritesNeedTheTokenReadsDoNot) {
  const std::string before = State();
  const std::string coil = CoilBody("K1", "C1", 1).dump();
  for (const std::string& auth :
       {std::string(), std::string("Bearer wrong"),
        std::string("Bearer s3cret-toke"), std::string("Bearer s3cret-tokenX"),
        std::string("Basic s3cret-token"), std::string(kToken)}) {
    const HttpResult r = PostWith("/v1/coils", coil, auth);
    EXPECT_EQ(r.status, 401) << auth << ": " << r.body;
    EXPECT_EQ(ErrorCode(r.body), "unauthorized") << r.body;
  }
  EXPECT_EQ(State(), before);
  HttpClient client(url_);
  EXPECT_EQ(client.Get("/v1/wear").status, 200);
  EXPECT_EQ(PostWith("/v1/coils", coil, std::string("Bearer ") + kToken).status,
            201);
}

TEST_F(HttpLimitsTest, BodyOverTheLimitIs413) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["padding"] = std::string(8192, 'x');
  const HttpResult r =
      PostWith("/v1/coils", coil.dump(), std::string("Bearer ") + kToken);
  EXPECT_EQ(r.status, 413) << r.body;
  EXPECT_EQ(ErrorCode(r.body), "payload_too_large") << r.body;
  EXPECT_EQ(State(), before);
}

TEST_F(HttpLimitsTest, TooManyOrTooLargeHeadersAre431) {
  const std::string before = State();
  const std::string body = CoilBody("K1", "C1", 1).dump();
  const std::string head =
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\n"
      "Authorization: Bearer " +
      std::string(kToken) +
      "\r\nContent-Type: application/json\r\n"
      "Content-Length: " +
      std::to_string(body.size()) + "\r\n";
  std::string many = head;
  for (int i = 0; i < 100; ++i) {
    many += "X-Filler-" + std::to_string(i) + ": y\r\n";
  }
  std::string answer = RawExchange(server_->port(), many + "\r\n" + body);
  EXPECT_EQ(answer.rfind("HTTP/1.1 431", 0), 0u) << answer;
  EXPECT_NE(answer.find("headers_too_large"), std::string::npos) << answer;

  std::string large = head;
  for (int i = 0; i < 6; ++i) {
    large +=
        "X-Big-" + std::to_string(i) + ": " + std::string(6000, 'z') + "\r\n";
  }
  answer = RawExchange(server_->port(), large + "\r\n" + body);
  EXPECT_EQ(answer.rfind("HTTP/1.1 431", 0), 0u) << answer;
  EXPECT_EQ(State(), before);

  // Within the limits the same request is fine.
  answer =
      RawExchange(server_->port(), head + "Connection: close\r\n\r\n" + body);
  EXPECT_EQ(answer.rfind("HTTP/1.1 201", 0), 0u) << answer;
}

TEST_F(HttpLimitsTest, DeepJsonNestingIs400BeforeParsing) {
  const std::string before = State();
  std::string deep = "{\"coil_id\":";
  for (int i = 0; i < 1000; ++i) deep += "[";
  for (int i = 0; i < 1000; ++i) deep += "]";
  deep += "}";
  const HttpResult r =
      PostWith("/v1/coils", deep, std::string("Bearer ") + kToken);
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(ErrorCode(r.body), "nesting_too_deep") << r.body;
  EXPECT_EQ(State(), before);
}

}  // namespace
}  // namespace rollwear::api::testing
