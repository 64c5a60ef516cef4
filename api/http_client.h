// HttpClient: a small keep-alive HTTP/1.1 client for rollwear's own tools
// (`rollwear replay`, the end-to-end tests, the load benchmark), wrapping
// cpp-httplib behind a pimpl so that only http_client.cc includes httplib.h.
// Connection failures are not errors of the API: they come back as
// status 0 with a message in `error`, so callers can retry (every POST of
// the API is idempotent).
//
// Thread-safety: not thread-safe; use one client per thread.
#ifndef ROLLWEAR_API_HTTP_CLIENT_H_
#define ROLLWEAR_API_HTTP_CLIENT_H_

#include <memory>
#include <string>

namespace rollwear::api {

struct HttpClientOptions {
  // Bearer token sent with every request; empty = none.
  std::string token;
  int connect_timeout_ms = 2000;
  int read_timeout_ms = 30000;
  int write_timeout_ms = 30000;
  bool keep_alive = true;
  bool tcp_nodelay = true;
};

struct HttpResult {
  int status = 0;  // 0 = no answer (connection refused, reset, timeout)
  std::string body;
  std::string error;  // set when status is 0
  // No connection could be made (refused, unreachable, connect timeout),
  // as opposed to one lost or timed out after it was made.
  bool not_connected = false;
  bool answered() const { return status != 0; }
};

class HttpClient {
 public:
  // `base_url` is "http://host:port" (no path).
  explicit HttpClient(const std::string& base_url,
                      const HttpClientOptions& options = {});
  ~HttpClient();

  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  HttpResult Get(const std::string& path);
  // JSON body.
  HttpResult Post(const std::string& path, const std::string& body);
  // Any method, with an explicit content type and optional extra header.
  HttpResult Send(const std::string& method, const std::string& path,
                  const std::string& body, const std::string& content_type,
                  const std::string& header_name = "",
                  const std::string& header_value = "");

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_CLIENT_H_
