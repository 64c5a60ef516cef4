// Internal to the HTTP server (api/http_server.h): the server's state (its
// Impl) and one connection's. http_server.cc holds the I/O thread's loop,
// accepting, the timeout sweep, dispatching requests to the router or the
// worker pool, taking their answers back (the completion queue), and
// Start/Stop; http_connection.cc holds a connection's I/O: reading,
// parsing, writing and flushing answers, lingering after "Connection:
// close"; http_limits.cc the limits: per-client accounting, refusals,
// pausing accept at the cap, deadlines and the sweep, fair turns, the
// input budget, the connection log and the Date header. Include only from
// those three files.
//
// Thread-safety: everything here belongs to the I/O thread, except Post()
// (any thread; it takes completions_mu) and the atomics.
#ifndef ROLLWEAR_API_HTTP_SERVER_INTERNAL_H_
#define ROLLWEAR_API_HTTP_SERVER_INTERNAL_H_

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <ctime>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <vector>

#include "api/http_parser.h"
#include "api/http_server.h"
#include "api/http_server_options.h"
#include "api/http_wire.h"
#include "api/metrics.h"
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
// Requests a connection may have handled in one turn of the I/O loop
// before the other ready connections get theirs.
inline constexpr int kRequestsPerTurn = 8;
// Bytes a connection may have read in one turn.
inline constexpr size_t kBytesPerTurn = 256 << 10;
// Buffers larger than this are given back after each request.
inline constexpr size_t kKeepBufferBytes = 64 << 10;
// Over the input budget, a connection with at least this much of a
// request buffered is not read (a head still fits).
inline constexpr size_t kBudgetExemptBytes = 64 << 10;

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
  bool prechecked = false;      // the head was checked (Router::PreCheck)
  bool in_ready = false;        // in Impl::ready (turn over, work left)
  bool budget_waiting = false;  // in Impl::budget_waiting
  int served = 0;
  uint64_t turn = 0;  // the loop turn turn_requests counts in
  int turn_requests = 0;
  size_t turn_bytes = 0;
  size_t in_accounted = 0;     // what Impl::buffered_in counts for this one
  size_t parsed_size = 0;      // the request's bytes at the last Parse()
  Clock::time_point deadline;  // the next one (the sweep closes)
  Clock::time_point phase_deadline;  // head's or body's total deadline
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

// Appends an answer: status line, Date, Content-Type, Content-Length, the
// response's headers, `connection` (header lines, each ending in CRLF, or
// ""), the blank line, and the body when `with_body`.
void AppendAnswer(std::string* out, const HttpResponse& response,
                  const std::string& date, std::string_view connection,
                  bool with_body);

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

  bool accept_at_cap = false;  // listener off: max_connections open

  std::unordered_map<uint64_t, std::unique_ptr<Conn>> conns;
  std::unordered_map<std::string, int> per_client;  // open conns by address
  // Connections whose turn ended with work left, resumed next loop turn.
  std::vector<uint64_t> ready;
  uint64_t turn = 0;
  // Request bytes buffered across connections (input buffers and bodies
  // being parsed, by capacity), and the connections not
  // read while it is over options.max_buffered_input_bytes.
  size_t buffered_in = 0;
  std::vector<uint64_t> budget_waiting;
  // The Date header's value, formatted once per second.
  time_t date_second = 0;
  std::string date_text;
  // The connection log's rate limit, per ConnectionEvent.
  std::vector<Clock::time_point> last_logged;
  std::vector<uint64_t> suppressed;
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

  // http_limits.cc: the limits.
  // Whether `addr` may open one more connection; counts it if so.
  bool AdmitClient(const std::string& addr);
  void ReleaseClient(const std::string& addr);
  // Answers 503 (Retry-After) on a fresh socket and closes it.
  void Refuse(int fd, const std::string& addr);
  // Turns the listener off at the cap, and back on below it.
  void PauseAcceptAtCap();
  void ResumeAcceptBelowCap();
  // Counts `event` in the metrics and logs it (rate-limited).
  void Note(ConnectionEvent event, const char* log_event, const char* reason,
            const std::string& remote);
  // Closes connections past their deadline, resumes accepting after EMFILE.
  void Sweep(Clock::time_point now);
  // Sets the head's total deadline when its first byte comes; after any
  // bytes of a request come, the next deadline: the total one of the head
  // or body, or the end of the longest pause (read_timeout), if sooner.
  void StartHead(Conn* c, Clock::time_point now);
  void OnProgress(Conn* c, Clock::time_point now);
  // Whether `c` has used its turn, for reading (kBytesPerTurn) or for
  // requests (kRequestsPerTurn); if so it is queued in `ready`.
  bool TurnOver(Conn* c, bool reading);
  // Queues `c` in `ready` (once).
  void MarkReady(Conn* c);
  // The open connection `id`, or null.
  Conn* Find(uint64_t id);
  // Resumes what `c` left: reading, or the requests it has in.
  void Resume(Conn* c);
  void RunReadyTurns();
  // Updates buffered_in after `c->in` changed; gives back a large empty
  // input buffer.
  void AccountInput(Conn* c);
  // Whether reading `c` must wait for the input budget (then it is queued).
  bool OverBudget(Conn* c);
  void ResumeBudgetWaiting();
  // "Tue, 24 Nov 2026 03:33:08 GMT", cached for the second.
  const std::string& Date();

  // http_connection.cc: one connection's I/O.
  void Close(Conn* c);
  // Reads until the socket is empty (edge-triggered) and parses, again
  // while reading stopped at the input cap and the requests read were
  // answered in place. May close `c`.
  void OnReadable(Conn* c);
  // Reads what the socket has, up to the input cap (then read_pending).
  void ReadSocket(Conn* c);
  // Parses and dispatches requests (ParseRequests) until one is with the
  // router, the input is used up or the turn is over. May close `c`.
  void ProcessInput(Conn* c);
  void ParseRequests(Conn* c);
  // A head is in and its body is not: the head's checks (answered and
  // closed when refused), the body's deadlines, "100 Continue".
  void OnHeadIn(Conn* c, Clock::time_point now, bool progress);
  // Queues the answer (one send for head and body) and flushes it. May
  // close `c`.
  void WriteAnswer(Conn* c, const HttpResponse& response);
  // Sends what is queued. May close `c`.
  void Flush(Conn* c);
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_SERVER_INTERNAL_H_
