// HttpServer: the daemon's HTTP/1.1 listener (cpp-httplib behind a pimpl,
// so that only http_server.cc includes httplib.h). Every request goes
// through Router::Handle; the server adds the socket concerns: bind address
// and port (0 = ephemeral, port() reports the bound one), a fixed pool of
// worker threads (one connection per thread while it is kept alive),
// keep-alive count and timeout, TCP_NODELAY, the payload limit (413 before
// the body is read), header count/size limits (431 before the body is
// read), read/write timeouts, per-route latency into
// Router::metrics(), and an optional per-request log hook.
//
// Thread-safety: Start() and Stop() from one controlling thread; requests
// are served on the pool's threads. Stop() is graceful: it closes the
// listening socket, lets in-flight requests finish and joins the pool.
#ifndef ROLLWEAR_API_HTTP_SERVER_H_
#define ROLLWEAR_API_HTTP_SERVER_H_

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "api/router.h"
#include "core/status.h"

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

struct HttpServerOptions {
  std::string bind_address = "127.0.0.1";
  int port = 0;  // 0 = ephemeral
  // Worker threads. A kept-alive connection holds one while it is open, so
  // this bounds the concurrent clients served without queueing.
  int threads = 32;
  int keep_alive_max_count = 10000;  // requests per connection
  int keep_alive_timeout_s = 5;      // idle seconds before closing
  int read_timeout_s = 5;
  int write_timeout_s = 5;
  size_t payload_max_bytes = 1 << 20;
  // Request header limits. cpp-httplib 0.11 (Debian 12, a compiled
  // library) caps each header line at 8 KiB and the request line at 8 KiB
  // (CPPHTTPLIB_HEADER_MAX_LENGTH / _REQUEST_URI_MAX_LENGTH, fixed when the
  // library was built) but not the number of header lines; a request with
  // more lines or more header bytes than these is answered 431 before its
  // body is read.
  size_t max_header_count = 64;
  size_t max_header_bytes = 32 * 1024;
  bool tcp_nodelay = true;
  // Called after every request on the serving thread; may be empty.
  std::function<void(const RequestLogEntry&)> on_request;

  bool IsValid(std::string* error) const;
};

class HttpServer {
 public:
  // `router` must outlive the server.
  HttpServer(Router* router, HttpServerOptions options);
  ~HttpServer();  // Stop()s

  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds and starts accepting on a background thread. Unavailable when the
  // address cannot be bound (in use, not local...).
  Status Start();
  // The bound port (after Start()).
  int port() const;
  // Graceful stop; idempotent.
  void Stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_SERVER_H_
