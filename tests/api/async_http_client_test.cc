// AsyncHttpClient (api/async_http_client.h) against a scripted server on a
// real loopback socket: every request ends once with its own answer over
// at most N connections; a refused connection, a lost answer, a timeout
// and broken chunk framing each end their request with status 0 and the right
// kind; a request lost on a stale keep-alive connection is sent once more
// (and is "not connected" when nothing listens any more); chunked answers
// are read; not_before holds a request back; `done` may queue more;
// cancelled requests end; a deadline already passed still reads.
#include "api/async_http_client.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "api/http_answer.h"

namespace rollwear::api {
namespace {

using Clock = std::chrono::steady_clock;

// What the server does with one request: send `bytes` (may be empty), then
// close the connection or keep it, or hang (never answer).
struct Reply {
  std::string bytes;
  bool close = false;
  bool hang = false;
  int close_after_ms = 0;  // with `close`: wait this long first
};

std::string Ok(const std::string& body, bool close = false) {
  return "HTTP/1.1 200 OK\r\nContent-Length: " + std::to_string(body.size()) +
         (close ? "\r\nConnection: close" : "") + "\r\n\r\n" + body;
}

// A request as the server read it: its connection (numbered from 0 as
// accepted), its number on that connection, its head and its body.
struct Seen {
  int conn = 0;
  int index = 0;
  std::string head;
  std::string body;
};

// A loopback server answering each request with `script(request)`, one
// thread per connection.
class ScriptedServer {
 public:
  using Script = std::function<Reply(const Seen&)>;

  explicit ScriptedServer(Script script) : script_(std::move(script)) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
    socklen_t len = sizeof(addr);
    getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len);
    port_ = ntohs(addr.sin_port);
    listen(fd_, 64);
    acceptor_ = std::thread([this] { Accept(); });
  }
  ~ScriptedServer() {
    stop_ = true;
    shutdown(fd_, SHUT_RDWR);
    close(fd_);
    acceptor_.join();
    std::lock_guard<std::mutex> lock(mu_);
    for (int c : conns_) shutdown(c, SHUT_RDWR);
    for (auto& t : threads_) t.join();
    for (int c : conns_) close(c);
  }
  std::string url() const {
    return "http://127.0.0.1:" + std::to_string(port_);
  }
  int port() const { return port_; }
  int connections() const { return accepted_.load(); }

 private:
  void Accept() {
    while (!stop_) {
      const int c = accept(fd_, nullptr, nullptr);
      if (c < 0) return;
      const int n = accepted_.fetch_add(1);
      std::lock_guard<std::mutex> lock(mu_);
      conns_.push_back(c);
      threads_.emplace_back([this, c, n] { Serve(c, n); });
    }
  }
  void Serve(int c, int conn) {
    std::string in;
    char buf[4096];
    for (int request = 0;; ++request) {
      size_t end;
      while ((end = in.find("\r\n\r\n")) == std::string::npos) {
        const ssize_t k = recv(c, buf, sizeof(buf), 0);
        if (k <= 0) return Close(c);
        in.append(buf, static_cast<size_t>(k));
      }
      const size_t at = in.find("Content-Length: ");
      const size_t length =
          at < end ? std::strtoul(in.c_str() + at + 16, nullptr, 10) : 0;
      while (in.size() < end + 4 + length) {
        const ssize_t k = recv(c, buf, sizeof(buf), 0);
        if (k <= 0) return Close(c);
        in.append(buf, static_cast<size_t>(k));
      }
      const Reply r = script_(Seen{conn, request, in.substr(0, end + 4),
                                   in.substr(end + 4, length)});
      in.erase(0, end + 4 + length);
      if (r.hang) {
        while (recv(c, buf, sizeof(buf), 0) > 0) {
        }
        return Close(c);
      }
      if (!r.bytes.empty()) send(c, r.bytes.data(), r.bytes.size(), 0);
      if (r.close) {
        std::this_thread::sleep_for(
            std::chrono::milliseconds(r.close_after_ms));
        return Close(c);
      }
    }
  }
  void Close(int c) { shutdown(c, SHUT_WR); }

  Script script_;
  int fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> accepted_{0};
  std::thread acceptor_;
  std::mutex mu_;
  std::vector<int> conns_;
  std::vector<std::thread> threads_;
};

// What a client's `done` was called with, in order.
struct Outcomes {
  std::vector<HttpResult> results;
  std::map<uint64_t, HttpResult> by_tag;
};

// A client of `server` reporting into `out`.
std::unique_ptr<AsyncHttpClient> ClientOf(const ScriptedServer& server,
                                          Outcomes* out,
                                          AsyncHttpOptions options = {}) {
  return std::make_unique<AsyncHttpClient>(
      server.url(), options, [out](uint64_t tag, const HttpResult& r) {
        out->results.push_back(r);
        out->by_tag[tag] = r;
      });
}

// Posts tags 1 and 2 and runs until both have ended.
void PostTwo(AsyncHttpClient* client) {
  client->Post("/a", "{}", 1);
  client->Post("/a", "{}", 2);
  client->RunUntilIdle();
}

AsyncHttpOptions OneConnection() {
  AsyncHttpOptions o;
  o.connections = 1;
  return o;
}

TEST(AsyncHttpClientTest, EveryRequestEndsOnceWithItsOwnAnswer) {
  ScriptedServer server(
      [](const Seen& r) { return Reply{Ok("echo:" + r.body)}; });
  Outcomes out;
  AsyncHttpOptions options;
  options.connections = 4;
  auto client = ClientOf(server, &out, options);
  for (uint64_t i = 0; i < 300; ++i) {
    client->Post("/v1/coils", "{\"n\":" + std::to_string(i) + "}", i);
  }
  client->RunUntilIdle();
  EXPECT_EQ(out.results.size(), 300u);
  ASSERT_EQ(out.by_tag.size(), 300u);
  for (uint64_t i = 0; i < 300; ++i) {
    EXPECT_EQ(out.by_tag[i].status, 200) << out.by_tag[i].error;
    EXPECT_EQ(out.by_tag[i].body, "echo:{\"n\":" + std::to_string(i) + "}");
  }
  EXPECT_LE(server.connections(), 4);
  EXPECT_GE(server.connections(), 1);
  EXPECT_EQ(client->pending(), 0u);
}

TEST(AsyncHttpClientTest, SendsThePathTheTokenAndTheWholeBody) {
  std::mutex mu;
  Seen seen;
  ScriptedServer server([&](const Seen& r) {
    std::lock_guard<std::mutex> lock(mu);
    seen = r;
    return Reply{Ok("{}")};
  });
  Outcomes out;
  AsyncHttpOptions options;
  options.token = "s3cret";
  auto client = ClientOf(server, &out, options);
  const std::string body(100000, 'x');  // larger than one socket write
  client->Post("/v1/coils", body, 7);
  client->RunUntilIdle();
  ASSERT_EQ(out.results.size(), 1u);
  EXPECT_EQ(out.results[0].status, 200);
  std::lock_guard<std::mutex> lock(mu);
  EXPECT_EQ(seen.head.rfind("POST /v1/coils HTTP/1.1\r\n", 0), 0u) << seen.head;
  EXPECT_NE(seen.head.find("\r\nAuthorization: Bearer s3cret\r\n"),
            std::string::npos)
      << seen.head;
  EXPECT_NE(seen.head.find("\r\nContent-Type: application/json\r\n"),
            std::string::npos);
  EXPECT_EQ(seen.body, body);
}

TEST(AsyncHttpClientTest, ARefusedConnectionIsNotConnected) {
  int port = 0;
  {
    ScriptedServer gone([](const Seen&) { return Reply{}; });
    port = gone.port();
  }
  Outcomes out;
  AsyncHttpClient client(
      "http://127.0.0.1:" + std::to_string(port), {},
      [&](uint64_t, const HttpResult& r) { out.results.push_back(r); });
  client.Post("/v1/coils", "{}", 1);
  client.RunUntilIdle();
  ASSERT_EQ(out.results.size(), 1u);
  const HttpResult& result = out.results[0];
  EXPECT_FALSE(result.answered());
  EXPECT_TRUE(result.not_connected) << result.error;
  EXPECT_NE(result.error.find("connect"), std::string::npos) << result.error;
}

TEST(AsyncHttpClientTest, AStaleKeepAliveConnectionIsReplacedOnce) {
  // Connection 0 answers (keep-alive) and closes 100 ms later, while the
  // client is idle: the client's next request meets the closed connection
  // before any byte of an answer and goes once more on connection 1.
  std::atomic<int> requests{0};
  ScriptedServer server([&](const Seen& r) {
    ++requests;
    return Reply{Ok(std::to_string(r.conn) + ":" + r.body), r.conn == 0, false,
                 100};
  });
  Outcomes out;
  auto client = ClientOf(server, &out, OneConnection());
  client->Post("/a", "1", 1);
  client->RunUntilIdle();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  client->Post("/a", "2", 2);
  client->RunUntilIdle();
  ASSERT_EQ(out.results.size(), 2u);
  EXPECT_EQ(out.results[0].body, "0:1");
  EXPECT_EQ(out.results[1].status, 200) << out.results[1].error;
  EXPECT_EQ(out.results[1].body, "1:2");
  EXPECT_EQ(server.connections(), 2);
  EXPECT_EQ(requests.load(), 2);  // the lost send never reached the server
}

TEST(AsyncHttpClientTest, AnAnswerLostAfterItsFirstByteIsNotSentAgain) {
  // On a reused connection the second answer breaks off after a few bytes:
  // the request may have been acted on, so it ends with no answer instead
  // of going again (the caller decides: the replay retries with its key).
  std::atomic<int> requests{0};
  ScriptedServer server([&](const Seen& r) {
    ++requests;
    if (r.index == 0) return Reply{Ok("{}")};
    return Reply{"HTTP/1.1 200 OK\r\nContent-Le", true, false};
  });
  Outcomes out;
  auto client = ClientOf(server, &out, OneConnection());
  PostTwo(client.get());
  ASSERT_EQ(out.results.size(), 2u);
  EXPECT_EQ(out.results[0].status, 200);
  EXPECT_FALSE(out.results[1].answered());
  EXPECT_FALSE(out.results[1].not_connected);
  EXPECT_EQ(requests.load(), 2);
  EXPECT_EQ(server.connections(), 1);
}

TEST(AsyncHttpClientTest, AnAnswerThatNeverComesTimesOut) {
  ScriptedServer server([](const Seen&) { return Reply{"", false, true}; });
  Outcomes out;
  AsyncHttpOptions options;
  options.answer_timeout_ms = 200;
  auto client = ClientOf(server, &out, options);
  const auto start = Clock::now();
  client->Post("/a", "{}", 1);
  client->RunUntilIdle();
  const double s = std::chrono::duration<double>(Clock::now() - start).count();
  ASSERT_EQ(out.results.size(), 1u);
  EXPECT_FALSE(out.results[0].answered());
  EXPECT_FALSE(out.results[0].not_connected);
  EXPECT_EQ(out.results[0].error, "answer timed out");
  EXPECT_GE(s, 0.2);
}

TEST(AsyncHttpClientTest, AChunkedAnswerIsReadAndTheConnectionKept) {
  // Two chunks with an extension and a trailer, then a second answer on the
  // same connection: the first must end exactly where its framing does.
  ScriptedServer server([](const Seen& r) {
    if (r.index == 0) {
      return Reply{
          "HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\n"
          "3;ext=1\r\n{\"a\r\n5\r\n\":12}\r\n0\r\nX-Trailer: t\r\n\r\n"};
    }
    return Reply{Ok("second")};
  });
  Outcomes out;
  auto client = ClientOf(server, &out, OneConnection());
  PostTwo(client.get());
  ASSERT_EQ(out.results.size(), 2u);
  EXPECT_EQ(out.by_tag[1].status, 200) << out.by_tag[1].error;
  EXPECT_EQ(out.by_tag[1].body, "{\"a\":12}");
  EXPECT_EQ(out.by_tag[2].body, "second");
  EXPECT_EQ(server.connections(), 1);
}

TEST(AsyncHttpClientTest, BrokenChunkFramingEndsTheRequestWithNoAnswer) {
  ScriptedServer server([](const Seen&) {
    return Reply{
        "HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n{}\r\n"};
  });
  Outcomes out;
  auto client = ClientOf(server, &out);
  client->Post("/a", "{}", 1);
  client->RunUntilIdle();
  ASSERT_EQ(out.results.size(), 1u);
  EXPECT_FALSE(out.results[0].answered());
  EXPECT_NE(out.results[0].error.find("chunked"), std::string::npos)
      << out.results[0].error;
}

TEST(AsyncHttpClientTest, ChunkedBodiesAreFramedExactly) {
  std::string body;
  size_t end = 0;
  const std::string in = "4\r\nWiki\r\n0\r\n\r\nNEXT";
  ASSERT_EQ(ChunkedBody(in, 0, &body, &end), 1);
  EXPECT_EQ(body, "Wiki");
  EXPECT_EQ(in.substr(end), "NEXT");
  for (size_t cut = 0; cut + 4 < in.size(); ++cut) {  // every prefix
    EXPECT_EQ(ChunkedBody(in.substr(0, cut), 0, &body, &end), 0) << cut;
  }
  EXPECT_EQ(ChunkedBody("4\r\nWikiXX0\r\n\r\n", 0, &body, &end), -1);
  EXPECT_EQ(ChunkedBody("g\r\n", 0, &body, &end), -1);
}

TEST(AsyncHttpClientTest, AStaleResendThatCannotConnectIsNotConnected) {
  // The daemon answered, then went away: the request lost on the stale
  // connection is sent again, finds nothing listening and ends as "not
  // connected" (the replay waits for a restart on that).
  auto server = std::make_unique<ScriptedServer>([](const Seen&) {
    return Reply{Ok("{}"), true, false, 100};
  });
  Outcomes out;
  auto client = ClientOf(*server, &out, OneConnection());
  client->Post("/a", "1", 1);
  client->RunUntilIdle();
  server.reset();
  client->Post("/a", "2", 2);
  client->RunUntilIdle();
  ASSERT_EQ(out.results.size(), 2u);
  EXPECT_EQ(out.results[0].status, 200);
  EXPECT_FALSE(out.results[1].answered());
  EXPECT_TRUE(out.results[1].not_connected) << out.results[1].error;
}

TEST(AsyncHttpClientTest, CancelledRequestsEndAndAPassedDeadlineStillReads) {
  std::atomic<int> requests{0};
  ScriptedServer server([&](const Seen&) {
    ++requests;
    return Reply{Ok("{}")};
  });
  Outcomes out;
  auto client = ClientOf(server, &out, OneConnection());
  for (uint64_t i = 0; i < 3; ++i) client->Post("/a", "{}", i);
  // A deadline in the past: the first request goes out; what has arrived
  // is read on a later call, however late.
  while (out.results.empty()) {
    client->RunUntil(Clock::now() - std::chrono::seconds(1));
  }
  EXPECT_EQ(out.by_tag[0].status, 200);
  client->CancelQueued();
  client->RunUntilIdle();
  ASSERT_EQ(out.results.size(), 3u);
  int cancelled = 0;
  for (uint64_t i = 1; i < 3; ++i) {
    if (out.by_tag[i].error == "cancelled") ++cancelled;
  }
  // The second went out as soon as the first ended (one connection); the
  // third never went.
  EXPECT_GE(cancelled, 1);
  EXPECT_EQ(requests.load() + cancelled, 3);
}

TEST(AsyncHttpClientTest,
     ConnectionCloseAnswersAreReadAndTheNextGoesOnANewOne) {
  ScriptedServer server([](const Seen& r) {
    return Reply{Ok(std::to_string(r.conn), true), true, false};
  });
  Outcomes out;
  auto client = ClientOf(server, &out, OneConnection());
  for (uint64_t i = 0; i < 3; ++i) client->Post("/a", "{}", i);
  client->RunUntilIdle();
  ASSERT_EQ(out.results.size(), 3u);
  for (uint64_t i = 0; i < 3; ++i) {
    EXPECT_EQ(out.by_tag[i].status, 200) << out.by_tag[i].error;
    EXPECT_EQ(out.by_tag[i].body, std::to_string(i));
  }
  EXPECT_EQ(server.connections(), 3);
}

TEST(AsyncHttpClientTest, NotBeforeHoldsARequestBackAndDoneMayQueueMore) {
  ScriptedServer server([](const Seen& r) { return Reply{Ok(r.body)}; });
  std::vector<std::string> order;
  Clock::time_point retried_at;
  const auto start = Clock::now();
  AsyncHttpClient* self = nullptr;
  AsyncHttpClient client(
      server.url(), {}, [&](uint64_t tag, const HttpResult& r) {
        order.push_back(r.body);
        if (tag == 1) {
          self->Post("/a", "again", 2,
                     Clock::now() + std::chrono::milliseconds(150));
        } else {
          retried_at = Clock::now();
        }
      });
  self = &client;
  client.Post("/a", "first", 1);
  client.RunUntilIdle();
  EXPECT_EQ(order, (std::vector<std::string>{"first", "again"}));
  EXPECT_GE(std::chrono::duration<double>(retried_at - start).count(), 0.15);
}

TEST(AsyncHttpClientTest, AnAnswerHeadIsParsed) {
  AnswerHead head;
  bool bad = false;
  EXPECT_FALSE(ParseAnswerHead("HTTP/1.1 200 OK\r\nContent-Len", &head, &bad));
  ASSERT_TRUE(ParseAnswerHead(
      "HTTP/1.1 409 Conflict\r\ncontent-length: 12\r\nConnection: close\r\n"
      "\r\n{\"error\":1}x",
      &head, &bad));
  EXPECT_FALSE(bad);
  EXPECT_EQ(head.status, 409);
  EXPECT_EQ(head.body_length, 12u);
  EXPECT_TRUE(head.close);
  EXPECT_FALSE(head.chunked);
  EXPECT_EQ(head.head_length, 64u);  // 23 + 20 + 19 + 2
  ASSERT_TRUE(ParseAnswerHead("garbage\r\n\r\n", &head, &bad));
  EXPECT_TRUE(bad);
}

}  // namespace
}  // namespace rollwear::api
