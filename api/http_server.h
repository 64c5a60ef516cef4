// HttpServer: the daemon's HTTP/1.1 listener. One epoll I/O thread owns
// every connection (read, parse with api/http_parser.h, answer in one
// send); each request runs as Router::Plan says: wear reads in place on the
// I/O thread, POST /v1/coils through the store's group commit without
// holding a thread (the answer comes back from the writer thread), and
// everything that may wait on SQLite on a fixed worker pool. So a kept-alive
// connection costs a socket and a few buffers, not a thread.
//
// The server adds the socket concerns to Router::Handle: bind address and
// port (0 = ephemeral, port() reports the bound one), keep-alive count and
// idle timeout, read timeout (the head of a request must arrive within it
// of its first byte; the body may pause at most that long), write timeout,
// TCP_NODELAY, pipelining (answers in request order), Expect:
// 100-continue, chunked request bodies, the payload limit (413 before the
// body is read), request line and header limits (414, 431), a connection
// cap, per-route latency into Router::metrics() and an optional
// per-request log hook.
//
// Thread-safety: Start() and Stop() from one controlling thread; requests
// are served on the I/O thread and the pool's threads. Stop() is graceful:
// it stops accepting, closes idle connections, lets requests in progress
// finish and be answered, then joins the threads. The router (and the store
// behind it) must outlive the server.
#ifndef ROLLWEAR_API_HTTP_SERVER_H_
#define ROLLWEAR_API_HTTP_SERVER_H_

#include <memory>

#include "api/http_server_options.h"
#include "api/router.h"
#include "core/base/status.h"

namespace rollwear::api {

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
