// Internal to the HTTP server (api/http_server.h): the server's state (its
// Impl) and one connection's. http_server.cc holds the I/O thread's loop,
// accepting, the timeout sweep, dispatching requests to the router or the
// worker pool, taking their answers back (the completion queue), and
// Start/Stop; http_connection.cc holds a connection's I/O: reading,
// parsing, writing and flushing answers, lingering after "Connection:
// close". Include only from those two files.
//
// Thread-safety: everything here belongs to the I/O thread, except Post()
// (any thread; it takes completions_mu) and the atomics.
#ifndef ROLLWEAR_API_HTTP_SERVER_INTERNAL_H_
#define ROLLWEAR_API_HTTP_SERVER_INTERNAL_H_

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "api/http_parser.h"
#include "api/http_server.h"
#include "api/http_server_options.h"
#include "api/http_wire.h"
#include "api/router.h"
#include "core/base/status.h"

namespace rollwear::api {
namespace server_internal {

using Clock = std::chrono::steady_clock;

inline constexpr uint64_t kListenTag = 0;
inline constexpr uint64_t kWakeTag = 1;
inline constexpr uint64_t kFirstConnId = 2;
// Sweep period for timeouts (they are whole seconds).
inline constexpr int kSweepMs = 100;
// After a "Connection: close" answer the server reads and drops what the
// client still sends (so that closing does not reset the answer away), for
// at most this long.
inline constexpr auto kLingerAfterClose = std::chrono::seconds(2);
// A client that pipelines requests without reading the answers is not read
// further while this many answer bytes wait for it.
inline constexpr size_t kMaxPendingOut = 1 << 20;

struct Conn {
  uint64_t id = 0;
  int fd = -1;
  std::string remote_addr;
  std::string in;  // received bytes; the parser sees in[in_start..]
  size_t in_start = 0;
  std::string out;  // answer bytes not yet sent start at out_sent
  size_t out_sent = 0;
  RequestParser parser;
  bool busy = false;          // a request is with the router
  bool read_pending = false;  // stopped reading before EAGAIN
  bool request_started = false;
  bool continue_sent = false;
  bool close_after_write = false;
  bool lingering = false;  // answered, write side shut, draining
  bool peer_closed = false;
  int served = 0;
  Clock::time_point deadline;
  // The request with the router.
  std::string method;
  std::string path;
  size_t request_bytes = 0;
  bool keep_alive = true;
  bool head = false;
  bool http10 = false;
  Clock::time_point started;

  explicit Conn(const HttpParserLimits& limits) : parser(limits) {}
};

struct Completion {
  uint64_t conn_id;
  HttpResponse response;
};

}  // namespace server_internal

struct HttpServer::Impl {
  using Clock = server_internal::Clock;
  using Conn = server_internal::Conn;
  using Completion = server_internal::Completion;

  Router* router = nullptr;
  HttpServerOptions options;
  HttpParserLimits limits;
  int listen_fd = -1;
  int epoll_fd = -1;
  int wake_fd = -1;
  int port = 0;
  bool started = false;
  std::thread loop;
  std::thread::id loop_id;
  std::unique_ptr<WorkerPool> pool;
  std::atomic<bool> stopping{false};
  bool accept_paused = false;
  Clock::time_point accept_resume;

  std::unordered_map<uint64_t, std::unique_ptr<Conn>> conns;
  uint64_t next_id = server_internal::kFirstConnId;
  // Requests with the router or a worker whose answer has not come back.
  int in_flight = 0;

  std::mutex completions_mu;
  std::vector<Completion> completions;
  std::vector<Completion> completions_spare;
  std::atomic<bool> wake_pending{false};

  // http_server.cc: setup, the loop, accepting, dispatch and completions.
  Status Bind();
  void Run();
  // While stopping: stop accepting, close what has nothing in progress.
  bool Drained();
  void Accept();
  void Dispatch(Conn* c, HttpRequest request);
  // From any thread: hands an answer to the I/O thread.
  // The writer answers a group's coils one after the other; one eventfd
  // write per wake-up of the I/O thread serves them all (a wake-up is the
  // dear part on a virtual machine). The I/O thread clears wake_pending
  // after draining the eventfd and before it takes the queue, so a post it
  // does not take finds the flag clear and writes again. The write is made
  // under the lock: the I/O thread cannot take this completion (and let
  // Stop() free the server) before Post is done with it.
  void Post(Completion completion);
  void RunCompletions();
  // The router's answer to the request `c` had with it.
  void Complete(Conn* c, HttpResponse response);
  void Sweep(Clock::time_point now);

  // http_connection.cc: one connection's I/O.
  void Close(Conn* c);
  // Reads until the socket is empty (edge-triggered) and parses, again
  // while reading stopped at the input cap and the requests read were
  // answered in place. May close `c`.
  void OnReadable(Conn* c);
  // Reads what the socket has, up to the input cap (then read_pending).
  void ReadSocket(Conn* c);
  // Parses and dispatches requests until one is with the router or the
  // input is used up. May close `c`.
  void ProcessInput(Conn* c);
  // Queues the answer (one send for head and body) and flushes it. May
  // close `c`.
  void WriteAnswer(Conn* c, const HttpResponse& response);
  // Sends what is queued. May close `c`.
  void Flush(Conn* c);
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_SERVER_INTERNAL_H_
