// The epoll HTTP/1.1 server (api/http_server.h) over real loopback
// sockets, on the real router and store: pipelining (answers in request
// order), Expect: 100-continue, chunked request bodies, HEAD, HTTP/1.0 and
// "Connection: close", the keep-alive count and idle timeout, the read
// timeout of an unfinished head or body, 16 concurrent keep-alive clients,
// a client that leaves without reading its answer, Stop() under load, and
// the protocol errors answered with the error body of the API contract.
//
// Time bounds are generous (a timeout of 1 s must close the connection
// within 4 s): they catch a connection that is never closed, not a slow
// one.
#include "api/http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "api/http_client.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

using Clock = std::chrono::steady_clock;

struct RawResponse {
  int status = 0;
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;

  std::string Header(const std::string& lower_name) const {
    const auto it = headers.find(lower_name);
    return it == headers.end() ? "" : it->second;
  }
};

std::string Lower(std::string s) {
  for (char& c : s) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return s;
}

// A client socket that sends raw bytes and reads answers with deadlines.
class RawConnection {
 public:
  explicit RawConnection(int port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    // A server that stops reading must not hang the test in send().
    timeval tv{15, 0};
    if (fd_ >= 0) setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof(tv));
    if (fd_ >= 0 &&
        connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~RawConnection() { Close(); }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  bool ok() const { return fd_ >= 0; }
  void Close() {
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
  }

  bool Send(const std::string& data) {
    size_t sent = 0;
    while (sent < data.size()) {
      const ssize_t n =
          send(fd_, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) return false;
      sent += static_cast<size_t>(n);
    }
    return true;
  }

  // Reads one answer (a 1xx, 204 or the answer to a HEAD has no body).
  std::optional<RawResponse> Read(bool head_request = false,
                                  int timeout_ms = 10000) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
    size_t end;
    while ((end = buffer_.find("\r\n\r\n")) == std::string::npos) {
      if (!Fill(deadline)) return std::nullopt;
    }
    RawResponse r;
    const std::string head = buffer_.substr(0, end + 2);
    buffer_.erase(0, end + 4);
    if (head.rfind("HTTP/1.1 ", 0) != 0 || head.size() < 12) {
      ADD_FAILURE() << "not an HTTP/1.1 status line: " << head;
      return std::nullopt;
    }
    r.status = std::stoi(head.substr(9, 3));
    size_t pos = head.find("\r\n") + 2;
    while (pos < head.size()) {
      const size_t eol = head.find("\r\n", pos);
      const std::string line = head.substr(pos, eol - pos);
      pos = eol + 2;
      const size_t colon = line.find(':');
      if (colon == std::string::npos) {
        ADD_FAILURE() << "malformed header line: " << line;
        continue;
      }
      std::string value = line.substr(colon + 1);
      while (!value.empty() && value.front() == ' ') value.erase(0, 1);
      r.headers[Lower(line.substr(0, colon))] = value;
    }
    if (head_request || r.status < 200 || r.status == 204 || r.status == 304) {
      return r;
    }
    if (Lower(r.Header("transfer-encoding")) == "chunked") {
      ADD_FAILURE() << "chunked answers are not expected";
      return std::nullopt;
    }
    const std::string length = r.Header("content-length");
    if (length.empty()) {
      ADD_FAILURE() << "answer without Content-Length";
      return std::nullopt;
    }
    const size_t n = std::stoul(length);
    while (buffer_.size() < n) {
      if (!Fill(deadline)) return std::nullopt;
    }
    r.body = buffer_.substr(0, n);
    buffer_.erase(0, n);
    return r;
  }

  // Whether the server closes the connection within `timeout_ms` (bytes
  // that still come are kept in extra()).
  bool WaitClosed(int timeout_ms) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
    while (true) {
      const int left = static_cast<int>(
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                Clock::now())
              .count());
      if (left <= 0) return false;
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, left) <= 0) continue;
      char buf[4096];
      const ssize_t n = recv(fd_, buf, sizeof(buf), 0);
      if (n == 0) return true;
      if (n < 0) return errno == ECONNRESET;
      buffer_.append(buf, static_cast<size_t>(n));
    }
  }

  const std::string& extra() const { return buffer_; }

 private:
  bool Fill(Clock::time_point deadline) {
    const int left =
        static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                             deadline - Clock::now())
                             .count());
    if (left <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, left) <= 0) return false;
    char buf[65536];
    const ssize_t n = recv(fd_, buf, sizeof(buf), 0);
    if (n <= 0) return false;
    buffer_.append(buf, static_cast<size_t>(n));
    return true;
  }

  int fd_ = -1;
  std::string buffer_;
};

std::string PostCoilRequest(const std::string& body,
                            const std::string& extra_headers = "") {
  return "POST /v1/coils HTTP/1.1\r\nHost: x\r\n"
         "Content-Type: application/json\r\nContent-Length: " +
         std::to_string(body.size()) + "\r\n" + extra_headers + "\r\n" + body;
}

const std::string kGetWear = "GET /v1/wear HTTP/1.1\r\nHost: x\r\n\r\n";

// The coil count of the first mounted roll in a GET /v1/wear answer.
int CoilsInWear(const std::string& body) {
  const json j = json::parse(body, nullptr, false);
  if (!j.is_object() || !j.contains("positions") || j["positions"].empty()) {
    return -1;
  }
  return j["positions"][0].value("coils", -1);
}

// A valid rolled_at for the n-th coil of a test: 07:00:00 plus n seconds
// (CoilBody's default only suits seq < 60).
std::string RolledAt(int n) {
  char text[32];
  std::snprintf(text, sizeof(text), "2026-03-01T%02d:%02d:%02dZ", 7 + n / 3600,
                n / 60 % 60, n % 60);
  return text;
}

std::string ErrorCode(const std::string& body) {
  const json j = json::parse(body, nullptr, false);
  if (!j.is_object() || !j.contains("error") || !j["error"].is_object()) {
    return "<no error body>";
  }
  return j["error"].value("code", "");
}

class HttpServerTest : public RouterTest {
 protected:
  void TearDown() override {
    if (server_) server_->Stop();
    server_.reset();
    RouterTest::TearDown();
  }

  void StartServer(HttpServerOptions options = {}) {
    server_ = std::make_unique<HttpServer>(router_.get(), std::move(options));
    const Status started = server_->Start();
    ASSERT_TRUE(started.ok()) << started.ToString();
    url_ = "http://127.0.0.1:" + std::to_string(server_->port());
  }

  std::set<std::string> StoredCoilIds() {
    StatusOr<Dataset> data = store_->ExportDataset();
    EXPECT_TRUE(data.ok()) << data.status().ToString();
    if (!data.ok()) return {};
    return std::set<std::string>(data->coil_ids.begin(), data->coil_ids.end());
  }

  std::unique_ptr<HttpServer> server_;
  std::string url_;
};

TEST_F(HttpServerTest, PipelinedRequestsAreAnsweredInOrder) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  const std::string coil = CoilBody("K1", "C1", 1).dump();
  ASSERT_TRUE(conn.Send(kGetWear +
                        "GET /v1/wear?x=1 HTTP/1.1\r\nHost: x\r\n\r\n" +
                        PostCoilRequest(coil)));
  const std::optional<RawResponse> a = conn.Read();
  const std::optional<RawResponse> b = conn.Read();
  const std::optional<RawResponse> c = conn.Read();
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->status, 200) << a->body;
  EXPECT_EQ(CoilsInWear(a->body), 0) << a->body;
  EXPECT_EQ(b->status, 200) << b->body;
  EXPECT_EQ(CoilsInWear(b->body), 0) << b->body;
  EXPECT_EQ(c->status, 201) << c->body;
  EXPECT_NE(c->body.find("\"K1\""), std::string::npos) << c->body;
  EXPECT_EQ(store_->Counters().coils, 1);
  // The connection is still open for more.
  ASSERT_TRUE(conn.Send(kGetWear));
  const std::optional<RawResponse> d = conn.Read();
  ASSERT_TRUE(d);
  EXPECT_EQ(CoilsInWear(d->body), 1) << d->body;
}

// A request sees the effect of the ones before it on the connection.
TEST_F(HttpServerTest, PipelinedWritesAndReadsRunInOrder) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send(PostCoilRequest(CoilBody("K1", "C1", 1).dump()) +
                        kGetWear +
                        PostCoilRequest(CoilBody("K2", "C1", 2).dump()) +
                        "GET /v1/wear/F6/top HTTP/1.1\r\nHost: x\r\n\r\n" +
                        "GET /nope HTTP/1.1\r\nHost: x\r\n\r\n"));
  std::vector<RawResponse> answers;
  for (int i = 0; i < 5; ++i) {
    std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r) << "answer " << i;
    answers.push_back(*r);
  }
  EXPECT_EQ(answers[0].status, 201) << answers[0].body;
  EXPECT_EQ(answers[1].status, 200);
  EXPECT_EQ(CoilsInWear(answers[1].body), 1) << answers[1].body;
  EXPECT_EQ(answers[2].status, 201) << answers[2].body;
  EXPECT_NE(answers[2].body.find("\"K2\""), std::string::npos);
  EXPECT_EQ(answers[3].status, 200);
  EXPECT_EQ(json::parse(answers[3].body, nullptr, false).value("coils", -1), 2)
      << answers[3].body;
  EXPECT_EQ(answers[4].status, 404);
  EXPECT_EQ(ErrorCode(answers[4].body), "not_found");
}

TEST_F(HttpServerTest, ExpectContinue) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  const std::string coil = CoilBody("K1", "C1", 1).dump();
  const std::string request = PostCoilRequest(coil, "Expect: 100-continue\r\n");
  ASSERT_TRUE(conn.Send(request.substr(0, request.size() - coil.size())));
  const std::optional<RawResponse> go = conn.Read();
  ASSERT_TRUE(go) << "no 100 Continue";
  EXPECT_EQ(go->status, 100);
  EXPECT_EQ(store_->Counters().coils, 0);
  ASSERT_TRUE(conn.Send(coil));
  const std::optional<RawResponse> done = conn.Read();
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, 201) << done->body;
  EXPECT_EQ(store_->Counters().coils, 1);
}

// A client that sends the body with the head gets no 100 Continue.
TEST_F(HttpServerTest, ExpectContinueWithTheBodyAlreadySent) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send(PostCoilRequest(CoilBody("K1", "C1", 1).dump(),
                                        "Expect: 100-continue\r\n")));
  const std::optional<RawResponse> r = conn.Read();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 201) << r->body;
}

TEST_F(HttpServerTest, ChunkedCoilIsStored) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  const std::string coil = CoilBody("K1", "C1", 1).dump();
  std::string request =
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\n"
      "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
  size_t pos = 0;
  for (const size_t size : {size_t{7}, size_t{100}, coil.size()}) {
    const std::string piece = coil.substr(pos, size);
    if (piece.empty()) break;
    char hex[32];
    std::snprintf(hex, sizeof(hex), "%zx", piece.size());
    request += std::string(hex) + ";piece=x\r\n" + piece + "\r\n";
    pos += piece.size();
  }
  ASSERT_EQ(pos, coil.size());
  request += "0\r\nX-Checksum: none\r\n\r\n";
  // In two sends, cut inside a chunk.
  ASSERT_TRUE(conn.Send(request.substr(0, request.size() / 2)));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(conn.Send(request.substr(request.size() / 2)));
  const std::optional<RawResponse> r = conn.Read();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 201) << r->body;
  EXPECT_EQ(store_->Counters().coils, 1);
  EXPECT_EQ(StoredCoilIds(), std::set<std::string>{"K1"});
}

// Chunk framing is not body: a body within the limit sent in tiny chunks
// (here 300 KB in 1-byte chunks, 1.8 MB on the wire) is read to its end.
TEST_F(HttpServerTest, BodyInTinyChunksIsReadToTheEnd) {
  StartServer();
  const std::string coil =
      CoilBody("K1", "C1", 1).dump() + std::string(300 * 1024, ' ');
  std::string request =
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\n"
      "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
  request.reserve(request.size() + coil.size() * 6 + 5);
  for (const char c : coil) {
    request += "1\r\n";
    request += c;
    request += "\r\n";
  }
  request += "0\r\n\r\n";
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  std::future<bool> sent =
      std::async(std::launch::async, [&] { return conn.Send(request); });
  const std::optional<RawResponse> r = conn.Read(false, 20000);
  EXPECT_TRUE(sent.get()) << "the server stopped reading the body";
  ASSERT_TRUE(r) << "no answer";
  EXPECT_EQ(r->status, 201) << r->body;
  EXPECT_EQ(store_->Counters().coils, 1);
}

TEST_F(HttpServerTest, HeadHasContentLengthButNoBody) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send(kGetWear));
  const std::optional<RawResponse> get = conn.Read();
  ASSERT_TRUE(get);
  ASSERT_EQ(get->status, 200);
  ASSERT_FALSE(get->body.empty());
  // HEAD then GET in one send: the GET's status line must follow the
  // HEAD's head directly.
  ASSERT_TRUE(
      conn.Send("HEAD /v1/wear HTTP/1.1\r\nHost: x\r\n\r\n" + kGetWear));
  const std::optional<RawResponse> head = conn.Read(/*head_request=*/true);
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_EQ(head->Header("content-length"), std::to_string(get->body.size()));
  const std::optional<RawResponse> again = conn.Read();
  ASSERT_TRUE(again) << "no answer after the HEAD (a body was sent?)";
  EXPECT_EQ(again->status, 200);
  EXPECT_EQ(again->body, get->body);
  EXPECT_TRUE(conn.extra().empty()) << conn.extra();
}

TEST_F(HttpServerTest, Http10IsClosedAfterTheAnswer) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send("GET /v1/wear HTTP/1.0\r\n\r\n"));
  const std::optional<RawResponse> r = conn.Read();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(CoilsInWear(r->body), 0);
  EXPECT_TRUE(conn.WaitClosed(4000));
}

TEST_F(HttpServerTest, Http10KeepAliveStaysOpen) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(
        conn.Send("GET /v1/wear HTTP/1.0\r\nConnection: keep-alive\r\n\r\n"));
    const std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r) << i;
    EXPECT_EQ(r->status, 200);
    // An HTTP/1.0 client closes unless the answer says keep-alive.
    EXPECT_EQ(Lower(r->Header("connection")), "keep-alive") << i;
  }
}

TEST_F(HttpServerTest, ConnectionCloseIsHonoured) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send(
      "GET /v1/wear HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
  const std::optional<RawResponse> r = conn.Read();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(Lower(r->Header("connection")), "close");
  EXPECT_TRUE(conn.WaitClosed(4000));
  EXPECT_TRUE(conn.extra().empty()) << conn.extra();
}

TEST_F(HttpServerTest, KeepAliveMaxCount) {
  HttpServerOptions options;
  options.keep_alive_max_count = 3;
  StartServer(options);
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  for (int i = 1; i <= 3; ++i) {
    ASSERT_TRUE(conn.Send(kGetWear)) << i;
    const std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r) << i;
    EXPECT_EQ(r->status, 200);
    if (i < 3) {
      EXPECT_NE(Lower(r->Header("connection")), "close") << i;
    } else {
      EXPECT_EQ(Lower(r->Header("connection")), "close");
    }
  }
  EXPECT_TRUE(conn.WaitClosed(4000));
}

TEST_F(HttpServerTest, IdleKeepAliveConnectionIsClosed) {
  HttpServerOptions options;
  options.keep_alive_timeout_s = 1;
  StartServer(options);
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(conn.Send(kGetWear));
    const std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }
  EXPECT_TRUE(conn.WaitClosed(4000)) << "idle connection still open after 4 s";
}

TEST_F(HttpServerTest, UnfinishedHeadIsClosedAfterTheReadTimeout) {
  HttpServerOptions options;
  options.read_timeout_s = 1;
  options.keep_alive_timeout_s = 30;
  StartServer(options);
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send("GET / HTTP/1.1\r\nHost: x\r\n"));
  EXPECT_TRUE(conn.WaitClosed(4000)) << "unfinished head kept open";
  // Nothing but possibly an error answer came back.
  EXPECT_TRUE(conn.extra().empty() || conn.extra().rfind("HTTP/1.1 4", 0) == 0)
      << conn.extra();
}

// A head trickled in one byte at a time still has to arrive within the
// read timeout.
TEST_F(HttpServerTest, TrickledHeadIsClosedAfterTheReadTimeout) {
  HttpServerOptions options;
  options.read_timeout_s = 1;
  options.head_timeout_s = 1;  // the total deadline; no pause is 1 s long
  options.keep_alive_timeout_s = 30;
  StartServer(options);
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  const auto start = Clock::now();
  bool closed = false;
  for (int i = 0; i < 40 && !closed; ++i) {
    if (!conn.Send("X")) break;  // the server closed; send may fail
    closed = conn.WaitClosed(100);
  }
  if (!closed) closed = conn.WaitClosed(4000);
  EXPECT_TRUE(closed);
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(8));
}

TEST_F(HttpServerTest, StalledBodyIsClosedAfterTheReadTimeout) {
  HttpServerOptions options;
  options.read_timeout_s = 1;
  options.keep_alive_timeout_s = 30;
  StartServer(options);
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  const std::string coil = CoilBody("K1", "C1", 1).dump();
  const std::string request = PostCoilRequest(coil);
  ASSERT_TRUE(conn.Send(request.substr(0, request.size() - 10)));
  EXPECT_TRUE(conn.WaitClosed(4000)) << "stalled body kept open";
  EXPECT_EQ(store_->Counters().coils, 0);
}

TEST_F(HttpServerTest, SixteenConcurrentKeepAliveClients) {
  StartServer();
  constexpr int kThreads = 16;
  constexpr int kCoils = 50;
  std::atomic<int> created{0};
  std::mutex mu;
  std::vector<std::string> failures;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      HttpClient client(url_);
      for (int i = 0; i < kCoils; ++i) {
        const std::string id =
            "T" + std::to_string(t) + "-" + std::to_string(i);
        const int seq = t * kCoils + i + 1;
        const HttpResult r = client.Post(
            "/v1/coils", CoilBody(id, "C1", seq, RolledAt(seq)).dump());
        if (r.status == 201) {
          created.fetch_add(1);
        } else {
          std::lock_guard<std::mutex> lock(mu);
          failures.push_back(id + ": " + std::to_string(r.status) + " " +
                             r.body + r.error);
        }
      }
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(created.load(), kThreads * kCoils);
  for (size_t i = 0; i < failures.size() && i < 5; ++i) {
    ADD_FAILURE() << failures[i];
  }
  EXPECT_EQ(store_->Counters().coils, kThreads * kCoils);
  EXPECT_EQ(StoredCoilIds().size(), static_cast<size_t>(kThreads * kCoils));
  // Every roll's wear counts each coil once.
  const json wear = json::parse(Get("/v1/wear").body, nullptr, false);
  ASSERT_TRUE(wear.contains("positions"));
  for (const json& p : wear["positions"]) {
    EXPECT_EQ(p.value("coils", -1), kThreads * kCoils) << p.dump();
  }
}

TEST_F(HttpServerTest, CoilOfAClientThatLeftIsStored) {
  StartServer();
  {
    RawConnection conn(server_->port());
    ASSERT_TRUE(conn.ok());
    ASSERT_TRUE(conn.Send(PostCoilRequest(CoilBody("K1", "C1", 1).dump())));
  }  // closed without reading
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  while (store_->Counters().coils < 1 && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(store_->Counters().coils, 1);
  EXPECT_EQ(StoredCoilIds(), std::set<std::string>{"K1"});
  // The server goes on serving.
  HttpClient client(url_);
  EXPECT_EQ(client.Get("/v1/wear").status, 200);
}

TEST_F(HttpServerTest, StopUnderLoadKeepsEveryAnsweredCoil) {
  StartServer();
  constexpr int kThreads = 16;
  std::atomic<bool> go{false};
  std::atomic<int> answered{0};
  std::mutex mu;
  std::vector<std::string> created;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      HttpClientOptions o;
      o.read_timeout_ms = 10000;
      o.connect_timeout_ms = 1000;
      HttpClient client(url_, o);
      while (!go.load()) std::this_thread::yield();
      for (int i = 0; i < 5000; ++i) {
        const std::string id =
            "S" + std::to_string(t) + "-" + std::to_string(i);
        const int seq = t * 5000 + i + 1;
        const HttpResult r = client.Post(
            "/v1/coils", CoilBody(id, "C1", seq, RolledAt(seq)).dump());
        if (!r.answered()) return;  // the server is gone
        answered.fetch_add(1);
        if (r.status == 201) {
          std::lock_guard<std::mutex> lock(mu);
          created.push_back(id);
        }
      }
    });
  }
  go.store(true);
  const auto start = Clock::now();
  while (answered.load() < 200 &&
         Clock::now() - start < std::chrono::seconds(10)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_GT(answered.load(), 0) << "no coil was answered before Stop()";
  std::future<void> stopped =
      std::async(std::launch::async, [this] { server_->Stop(); });
  if (stopped.wait_for(std::chrono::seconds(30)) != std::future_status::ready) {
    ADD_FAILURE() << "Stop() did not return within 30 s";
    std::fflush(stdout);
    std::abort();  // the destructor would hang too
  }
  for (std::thread& t : threads) t.join();
  const std::set<std::string> stored = StoredCoilIds();
  size_t missing = 0;
  for (const std::string& id : created) {
    if (!stored.count(id)) {
      if (++missing <= 5) ADD_FAILURE() << id << " got 201 but is not stored";
    }
  }
  EXPECT_EQ(missing, 0u) << "of " << created.size() << " coils";
  EXPECT_GE(stored.size(), created.size());
  // Stop() is idempotent.
  server_->Stop();
}

TEST_F(HttpServerTest, UnknownMethodIsAJsonError) {
  StartServer();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send("BREW / HTTP/1.1\r\nHost: x\r\n\r\n"));
  const std::optional<RawResponse> r = conn.Read();
  ASSERT_TRUE(r);
  EXPECT_GE(r->status, 400);
  EXPECT_LT(r->status, 500);
  EXPECT_NE(ErrorCode(r->body), "<no error body>") << r->body;
  EXPECT_NE(ErrorCode(r->body), "") << r->body;
  EXPECT_EQ(r->Header("content-type"), "application/json");
}

TEST_F(HttpServerTest, OversizedContentLengthIs413BeforeTheBody) {
  StartServer();
  const std::string before = State();
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send(
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Content-Length: " +
      std::to_string((1 << 20) + 1) + "\r\n\r\n"));
  const std::optional<RawResponse> r = conn.Read(false, 5000);
  ASSERT_TRUE(r) << "no answer before the body";
  EXPECT_EQ(r->status, 413) << r->body;
  EXPECT_EQ(ErrorCode(r->body), "payload_too_large") << r->body;
  EXPECT_TRUE(conn.WaitClosed(4000));
  EXPECT_EQ(State(), before);
}

// Request smuggling attempts are refused with a JSON 400 and the
// connection is closed (what follows must not be read as a request).
TEST_F(HttpServerTest, AmbiguousFramingIs400AndCloses) {
  StartServer();
  const std::string before = State();
  for (const std::string& head : {
           std::string("Content-Length: 4\r\nTransfer-Encoding: chunked\r\n"),
           std::string("Content-Length: 4\r\nContent-Length: 5\r\n"),
           std::string("Content-Length : 4\r\n"),
       }) {
    RawConnection conn(server_->port());
    ASSERT_TRUE(conn.ok());
    ASSERT_TRUE(conn.Send("POST /v1/coils HTTP/1.1\r\nHost: x\r\n" + head +
                          "\r\n0\r\n\r\n" + kGetWear));
    const std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r) << head;
    EXPECT_EQ(r->status, 400) << head << r->body;
    EXPECT_EQ(ErrorCode(r->body), "bad_request") << r->body;
    EXPECT_EQ(Lower(r->Header("connection")), "close") << head;
    EXPECT_TRUE(conn.WaitClosed(4000)) << head;
    EXPECT_TRUE(conn.extra().empty()) << head << ": " << conn.extra();
  }
  EXPECT_EQ(State(), before);
}

TEST_F(HttpServerTest, UnsupportedVersionAndCodingAreJsonErrors) {
  StartServer();
  {
    RawConnection conn(server_->port());
    ASSERT_TRUE(conn.Send("GET /v1/wear HTTP/2.0\r\nHost: x\r\n\r\n"));
    const std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 505);
    EXPECT_NE(ErrorCode(r->body), "<no error body>");
  }
  {
    RawConnection conn(server_->port());
    ASSERT_TRUE(
        conn.Send("POST /v1/coils HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: "
                  "gzip\r\n\r\n"));
    const std::optional<RawResponse> r = conn.Read();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 501);
    EXPECT_NE(ErrorCode(r->body), "<no error body>");
  }
}

// on_activity (what keeps the CPU wake-up limit held, service/
// cpu_latency.h) runs when traffic wakes the I/O thread, before the
// request is answered, and not on the idle thread's periodic sweeps.
TEST_F(HttpServerTest, OnActivityRunsForTrafficOnly) {
  auto calls = std::make_shared<std::atomic<int>>(0);
  HttpServerOptions options;
  options.on_activity = [calls] { calls->fetch_add(1); };
  StartServer(options);
  // Idle: several sweep periods pass without a call.
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  EXPECT_EQ(calls->load(), 0);
  RawConnection conn(server_->port());
  ASSERT_TRUE(conn.ok());
  ASSERT_TRUE(conn.Send(kGetWear));
  ASSERT_TRUE(conn.Read());
  const int after_one = calls->load();
  EXPECT_GE(after_one, 1);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(conn.Send(kGetWear));
    ASSERT_TRUE(conn.Read());
  }
  // Each request after the first woke the idle thread at least once.
  EXPECT_GE(calls->load(), after_one + 5);
}

}  // namespace
}  // namespace rollwear::api::testing
