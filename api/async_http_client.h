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
// Answers are framed by Content-Length (what rollwear's server and nginx
// in front of it send); a chunked answer ends its request with status 0
// and an error saying so.
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
  // every queued request.
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
  // comes first; true when none is left.
  bool RunUntil(Clock::time_point until);
  // Requests queued or in flight.
  size_t pending() const;

 private:
  class Loop;
  std::unique_ptr<Loop> loop_;
};

// The head of an HTTP/1.1 answer at the start of a connection's input.
struct AnswerHead {
  int status = 0;
  size_t body_length = 0;  // Content-Length (0 when absent)
  size_t head_length = 0;  // up to and including the blank line
  bool close = false;      // "Connection: close"
  bool chunked = false;    // "Transfer-Encoding: chunked"
};
// Parses the head at the start of `in`; false while it is incomplete. Sets
// *bad when it cannot be an HTTP/1.x answer.
bool ParseAnswerHead(std::string_view in, AnswerHead* head, bool* bad);
// Appends what the non-blocking socket `fd` holds to *in until a read would
// block; *closed when the peer has ended the stream (an answer and the FIN
// may come together: the answer is read first). 0, or the errno of a
// failed read.
int ReadAvailable(int fd, std::string* in, bool* closed);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_ASYNC_HTTP_CLIENT_H_
