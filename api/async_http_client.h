// AsyncHttpClient: one thread driving N keep-alive HTTP/1.1 connections
// with epoll, for rollwear's own tools that send many requests
// (`rollwear replay`). A blocking client thread per connection
// (HttpClient) costs ~45 µs of CPU per request on loopback, most of it in
// the kernel (a poll before every read and write, a thread switch per
// answer); this loop reads every ready answer per wake-up, as
// bench/load_client.h does, and costs a fraction of that. The difference
// matters because the tool runs on the daemon's cores (docs/performance.md,
// the replay).
//
// Requests are queued with a tag and sent in order as connections come
// free, not before their `not_before` time; each ends exactly once in the
// `done` callback with an HttpResult as HttpClient gives it: status 0 with
// `error` (and `not_connected` when no connection could be made) when
// there was no answer. A request lost on a reused keep-alive connection
// before any byte of its answer (the server closed the idle connection) is
// sent once more on a new connection, as HTTP clients do for idempotent
// requests; every POST of the API is (an idempotency key).
//
// The URL's host is resolved when a connection opens, and each of its
// addresses is tried in turn ("localhost" may be ::1 before 127.0.0.1).
// Answers are framed by Content-Length or chunked (api/http_answer.h).
//
// Thread-safety: not thread-safe. One thread calls every method; `done`
// runs on it, inside RunUntil/RunUntilIdle, and may queue more requests.
#ifndef ROLLWEAR_API_ASYNC_HTTP_CLIENT_H_
#define ROLLWEAR_API_ASYNC_HTTP_CLIENT_H_

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "api/http_answer.h"
#include "api/http_client.h"

namespace rollwear::api {

struct AsyncHttpOptions {
  // Bearer token sent with every request; empty = none.
  std::string token;
  int connections = 16;
  int connect_timeout_ms = 2000;
  // From a request's first byte sent to its whole answer read.
  int answer_timeout_ms = 30000;
};

class AsyncHttpClient {
 public:
  using Clock = std::chrono::steady_clock;
  using Done = std::function<void(uint64_t tag, const HttpResult& result)>;

  // `base_url` is "http://host:port" (no path). `done` is called once for
  // every queued request that ends before the client is destroyed.
  AsyncHttpClient(const std::string& base_url, const AsyncHttpOptions& options,
                  Done done);
  ~AsyncHttpClient();

  AsyncHttpClient(const AsyncHttpClient&) = delete;
  AsyncHttpClient& operator=(const AsyncHttpClient&) = delete;

  // Queues a POST of the JSON `body` to `path`, sent once a connection is
  // free and not before `not_before`.
  void Post(const std::string& path, const std::string& body, uint64_t tag,
            Clock::time_point not_before = {});
  // Runs until every queued request has ended (those `done` queues too).
  void RunUntilIdle();
  // Runs until `until` or until every queued request has ended, whichever
  // comes first (a deadline already passed still reads what is ready);
  // true when none is left.
  bool RunUntil(Clock::time_point until);
  // Ends every queued request not yet sent with status 0 and the error
  // "cancelled" (in flight ones run to their end).
  void CancelQueued();
  // Requests queued or in flight.
  size_t pending() const;

 private:
  class Loop;
  std::unique_ptr<Loop> loop_;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_ASYNC_HTTP_CLIENT_H_
