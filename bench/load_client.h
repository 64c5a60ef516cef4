// load_client: the load generator of load_bench. One thread drives N
// keep-alive HTTP/1.1 connections with epoll (the way wrk does), sending
// pre-built request bytes and reading each answer's status line and
// Content-Length body. It costs far less CPU per request than a blocking
// client thread per connection, which matters because the generator runs on
// the same cores as the daemon it measures: every microsecond it spends is
// taken from the daemon. Its own CPU time is reported with the figures.
//
// Two modes:
//  - closed loop (rate == 0): each connection sends its next request as soon
//    as the answer to the previous one is read; latency = send to answer.
//  - open loop (rate > 0), paced per connection as wrk2 does: request i is
//    due at start + i / rate and goes on connection i mod N, so each
//    connection carries rate / N requests/s; latency is counted from the
//    due time, so a stall counts for every request it delays.
// A connection the server closes (Connection: close, or EOF between
// answers) is reopened; a request whose answer was lost counts as a
// failure and is not retried.
//
// Thread-safety: RunLoad is reentrant (no shared state); call it from one
// thread per load.
#ifndef ROLLWEAR_BENCH_LOAD_CLIENT_H_
#define ROLLWEAR_BENCH_LOAD_CLIENT_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rollwear::bench {

struct LoadOptions {
  int port = 0;           // 127.0.0.1:port
  int connections = 16;   // concurrent keep-alive connections
  double rate = 0;        // requests/s (open loop); 0 = closed loop
  int expect_status = 0;  // answers with another status are failures
  double timeout_s = 30;  // the whole run is abandoned after this
};

struct LoadResult {
  int64_t answered = 0;
  int64_t failures = 0;           // other status, lost answer, timeout
  std::vector<double> latency_s;  // one per answered request
  // The same from the moment the request was sent (open loop: without the
  // time the client's own timer fired late).
  std::vector<double> from_send_s;
  std::map<int, int64_t> statuses;  // status code -> count
  double seconds = 0;               // first send to last answer
  double client_cpu_s = 0;          // this thread's user+system CPU
  std::string first_error;          // what went wrong first, if anything
};

// The bytes of one HTTP/1.1 request with a keep-alive connection.
std::string RequestBytes(const std::string& method, const std::string& path,
                         const std::string& body = "");

// Sends every request of `requests` once, in order, over the connections.
LoadResult RunLoad(const LoadOptions& options,
                   const std::vector<std::string>& requests);

}  // namespace rollwear::bench

#endif  // ROLLWEAR_BENCH_LOAD_CLIENT_H_
