#include "api/http_server.h"

#include <sys/socket.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <utility>

#include <httplib.h>

#include "api/codec.h"

namespace rollwear::api {
namespace {

HttpRequest ToRequest(const httplib::Request& req) {
  HttpRequest r;
  r.method = req.method;
  r.path = req.path;
  r.body = req.body;
  r.headers.reserve(req.headers.size());
  for (const auto& [key, value] : req.headers)
    r.headers.emplace_back(key, value);
  for (const auto& [key, value] : req.params) r.params.emplace(key, value);
  return r;
}

// Error body for answers that httplib gives before any handler runs
// (413 payload too large, 400 bad request line, 414 URI too long).
std::string ErrorBodyFor(int status) {
  ApiError e{status, "bad_request", "malformed HTTP request", ""};
  if (status == 413) {
    e.code = "payload_too_large";
    e.message = "the body is larger than the configured limit";
  } else if (status == 414) {
    e.code = "uri_too_long";
    e.message = "the request URI is too long";
  } else if (status == 431) {
    e.code = "headers_too_large";
    e.message = "the request has too many or too large header fields";
  } else if (status == 404) {
    e.code = "not_found";
    e.message = "no such endpoint";
  } else if (status >= 500) {
    e.code = "internal";
    e.message = "internal error";
  }
  return EncodeError(e);
}

}  // namespace

bool HttpServerOptions::IsValid(std::string* error) const {
  if (port < 0 || port > 65535) {
    *error = "port must be in [0, 65535]";
    return false;
  }
  if (threads < 1 || threads > 4096) {
    *error = "threads must be in [1, 4096]";
    return false;
  }
  if (keep_alive_max_count < 1) {
    *error = "keep_alive_max must be >= 1";
    return false;
  }
  if (keep_alive_timeout_s < 1 || read_timeout_s < 1 || write_timeout_s < 1) {
    *error = "timeouts must be >= 1 s";
    return false;
  }
  if (max_header_count < 8 || max_header_bytes < 1024) {
    *error = "header limits must be >= 8 fields and >= 1024 bytes";
    return false;
  }
  if (payload_max_bytes < 256) {
    *error = "payload limit must be >= 256 bytes";
    return false;
  }
  if (bind_address.empty()) {
    *error = "bind address must not be empty";
    return false;
  }
  return true;
}

struct HttpServer::Impl {
  Router* router;
  HttpServerOptions options;
  httplib::Server server;
  std::thread listener;
  int port = 0;
  bool started = false;
  std::atomic<bool> exited{false};

  void Serve(const httplib::Request& req, httplib::Response& res) {
    const auto start = std::chrono::steady_clock::now();
    const HttpResponse out = router->Handle(ToRequest(req));
    res.status = out.status;
    for (const auto& [key, value] : out.headers) res.set_header(key, value);
    res.set_content(out.body, out.content_type);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    router->metrics()->ObserveRequest(out.route, out.status, seconds);
    if (options.on_request) {
      options.on_request(RequestLogEntry{req.method, req.path, req.remote_addr,
                                         out.status, seconds, req.body.size(),
                                         out.body.size()});
    }
  }
};

HttpServer::HttpServer(Router* router, HttpServerOptions options)
    : impl_(std::make_unique<Impl>()) {
  impl_->router = router;
  impl_->options = std::move(options);
}

HttpServer::~HttpServer() { Stop(); }

Status HttpServer::Start() {
  std::string error;
  if (!impl_->options.IsValid(&error)) return Status::InvalidArgument(error);
  if (impl_->started) return Status::FailedPrecondition("already started");
  Impl* impl = impl_.get();
  httplib::Server& s = impl->server;
  const HttpServerOptions& o = impl->options;

  const int threads = o.threads;
  s.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  s.set_tcp_nodelay(o.tcp_nodelay);
  // SO_REUSEADDR only (no SO_REUSEPORT): a restarted daemon can rebind
  // through TIME_WAIT, but two daemons never share a port.
  s.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  s.set_keep_alive_max_count(static_cast<size_t>(o.keep_alive_max_count));
  s.set_keep_alive_timeout(o.keep_alive_timeout_s);
  s.set_read_timeout(o.read_timeout_s, 0);
  s.set_write_timeout(o.write_timeout_s, 0);
  s.set_payload_max_length(o.payload_max_bytes);

  // cpp-httplib 0.11 reads a POST/PUT/PATCH/DELETE without Content-Length
  // or chunked encoding until the connection closes (a 400 after the read
  // timeout on a kept-alive connection). Such a request has no body
  // (RFC 9112 6.3), e.g. `curl -X POST .../v1/calibrations`: say so before
  // the body is read. The request object is a non-const local of httplib's
  // request loop, so the cast is well-defined.
  const size_t max_header_count = o.max_header_count;
  const size_t max_header_bytes = o.max_header_bytes;
  s.set_pre_routing_handler(
      [max_header_count, max_header_bytes](const httplib::Request& req,
                                           httplib::Response& res) {
        size_t header_bytes = 0;
        for (const auto& [key, value] : req.headers) {
          header_bytes += key.size() + value.size() + 4;  // ": " and CRLF
        }
        if (req.headers.size() > max_header_count ||
            header_bytes > max_header_bytes) {
          res.status = 431;
          res.set_header("Connection", "close");
          res.set_content(ErrorBodyFor(431), "application/json");
          return httplib::Server::HandlerResponse::Handled;
        }
        if (!req.has_header("Content-Length") &&
            !req.has_header("Transfer-Encoding")) {
          const_cast<httplib::Request&>(req).set_header("Content-Length", "0");
        }
        return httplib::Server::HandlerResponse::Unhandled;
      });
  auto handler = [impl](const httplib::Request& req, httplib::Response& res) {
    impl->Serve(req, res);
  };
  s.Get(".*", handler);
  s.Post(".*", handler);
  s.Put(".*", handler);
  s.Patch(".*", handler);
  s.Delete(".*", handler);
  s.Options(".*", handler);
  s.set_error_handler(httplib::Server::HandlerWithResponse(
      [impl](const httplib::Request& req, httplib::Response& res) {
        // Answers of our handler already carry their JSON body.
        if (!res.body.empty())
          return httplib::Server::HandlerResponse::Unhandled;
        res.set_content(ErrorBodyFor(res.status), "application/json");
        impl->router->metrics()->ObserveRequest(RouteId::kUnmatched, res.status,
                                                0);
        return httplib::Server::HandlerResponse::Handled;
      }));
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res,
                             const std::exception_ptr&) {
    res.status = 500;
    res.set_content(ErrorBodyFor(500), "application/json");
  });

  if (o.port == 0) {
    impl->port = s.bind_to_any_port(o.bind_address);
    if (impl->port < 0) {
      return Status::Unavailable("cannot bind an ephemeral port on " +
                                 o.bind_address);
    }
  } else {
    if (!s.bind_to_port(o.bind_address, o.port)) {
      return Status::Unavailable("cannot bind " + o.bind_address + ":" +
                                 std::to_string(o.port) +
                                 " (address in use or not local?)");
    }
    impl->port = o.port;
  }
  impl->listener = std::thread([impl] {
    impl->server.listen_after_bind();
    impl->exited.store(true);
  });
  impl->started = true;
  // httplib's stop() only acts once the accept loop runs; wait for it so
  // that a Stop() right after Start() cannot be lost.
  while (!s.is_running() && !impl->exited.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return Status::Ok();
}

int HttpServer::port() const { return impl_->port; }

void HttpServer::Stop() {
  if (!impl_ || !impl_->started) return;
  impl_->server.stop();
  if (impl_->listener.joinable()) impl_->listener.join();
  impl_->started = false;
}

}  // namespace rollwear::api
