// The options of the daemon's HTTP server (api/http_server.h) and the entry
// its access-log hook receives. Apart from the server so that the socket
// helpers (api/http_wire.cc, which checks the options) and the server do
// not include each other.
//
// Thread-safety: plain values.
#ifndef ROLLWEAR_API_HTTP_SERVER_OPTIONS_H_
#define ROLLWEAR_API_HTTP_SERVER_OPTIONS_H_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace rollwear::api {

// One answered request, for the access log.
struct RequestLogEntry {
  std::string method;
  std::string path;
  std::string remote_addr;
  int status = 0;
  double seconds = 0;
  size_t request_bytes = 0;
  size_t response_bytes = 0;
};

// A refused, timed-out or throttled connection, for the log (at most one
// entry per event kind and second; `suppressed` counts the ones not logged
// since the last entry of that kind).
struct ConnectionLogEntry {
  const char* event = "";   // "connection_refused", "connection_timeout"...
  const char* reason = "";  // "per_client_limit", "head_deadline"...
  std::string remote_addr;
  uint64_t suppressed = 0;
};

struct HttpServerOptions {
  std::string bind_address = "127.0.0.1";
  int port = 0;  // 0 = ephemeral
  // Worker threads for the requests that may wait on SQLite or a
  // calibration (everything but coils and wear reads).
  int threads = 32;
  // Open connections; at the cap the server stops accepting (new ones wait
  // in the kernel's backlog) until one closes.
  int max_connections = 1000;
  // Open connections from one client address; one more is answered 503
  // (Retry-After) and closed.
  int max_connections_per_client = 64;
  int keep_alive_max_count = 10000;  // requests per connection
  int keep_alive_timeout_s = 5;      // idle seconds before closing
  // A request's head must be in within head_timeout_s of its first byte,
  // and its body within body_timeout_s of the head's end; the body may
  // also pause at most read_timeout_s. The timeouts restart on nothing.
  int head_timeout_s = 10;
  int body_timeout_s = 60;
  int read_timeout_s = 5;
  int write_timeout_s = 5;
  // Request bytes buffered across all connections; over it, connections
  // with more than 64 KiB of a request in are not read until it drops.
  size_t max_buffered_input_bytes = size_t{64} << 20;
  size_t payload_max_bytes = 1 << 20;
  // Request header limits: a request with more header lines or more header
  // bytes than these is answered 431 before its body is read. The request
  // line is capped at 8 KiB (414).
  size_t max_header_count = 64;
  size_t max_header_bytes = 32 * 1024;
  bool tcp_nodelay = true;
  // Called after every request on the serving thread; may be empty.
  std::function<void(const RequestLogEntry&)> on_request;
  // Called on the I/O thread each time it wakes up with work (input,
  // a new connection, a completion), before handling it; may be empty.
  // Must be cheap: it runs ahead of every batch of requests.
  std::function<void()> on_activity;
  // Called on the I/O thread for refused, timed-out and throttled
  // connections (rate-limited, see ConnectionLogEntry); may be empty.
  std::function<void(const ConnectionLogEntry&)> on_connection_event;

  bool IsValid(std::string* error) const;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_SERVER_OPTIONS_H_
