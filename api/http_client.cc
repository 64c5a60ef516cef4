#include "api/http_client.h"

#include <utility>

#include <httplib.h>

namespace rollwear::api {

struct HttpClient::Impl {
  explicit Impl(const std::string& url) : client(url) {}
  httplib::Client client;
  httplib::Headers headers;
};

HttpClient::HttpClient(const std::string& base_url,
                       const HttpClientOptions& options)
    : impl_(std::make_unique<Impl>(base_url)) {
  httplib::Client& c = impl_->client;
  c.set_keep_alive(options.keep_alive);
  c.set_tcp_nodelay(options.tcp_nodelay);
  // httplib takes (seconds, microseconds).
  auto split = [](int ms, auto set) {
    set(static_cast<time_t>(ms / 1000), static_cast<time_t>(ms % 1000) * 1000);
  };
  split(options.connect_timeout_ms,
        [&c](time_t s, time_t us) { c.set_connection_timeout(s, us); });
  split(options.read_timeout_ms,
        [&c](time_t s, time_t us) { c.set_read_timeout(s, us); });
  split(options.write_timeout_ms,
        [&c](time_t s, time_t us) { c.set_write_timeout(s, us); });
  if (!options.token.empty()) {
    impl_->headers.emplace("Authorization", "Bearer " + options.token);
  }
}

HttpClient::~HttpClient() = default;

HttpResult HttpClient::Get(const std::string& path) {
  return Send("GET", path, "", "");
}

HttpResult HttpClient::Post(const std::string& path, const std::string& body) {
  return Send("POST", path, body, "application/json");
}

HttpResult HttpClient::Send(const std::string& method, const std::string& path,
                            const std::string& body,
                            const std::string& content_type,
                            const std::string& header_name,
                            const std::string& header_value) {
  httplib::Headers headers = impl_->headers;
  if (!header_name.empty()) headers.emplace(header_name, header_value);
  httplib::Client& c = impl_->client;
  httplib::Result r{nullptr, httplib::Error::Unknown};
  if (method == "GET") {
    r = c.Get(path, headers);
  } else if (method == "HEAD") {
    r = c.Head(path, headers);
  } else if (method == "POST") {
    r = c.Post(path, headers, body, content_type);
  } else if (method == "PUT") {
    r = c.Put(path, headers, body, content_type);
  } else if (method == "DELETE") {
    r = c.Delete(path, headers, body, content_type);
  } else if (method == "PATCH") {
    r = c.Patch(path, headers, body, content_type);
  } else {
    HttpResult out;
    out.error = "unsupported method " + method;
    return out;
  }
  HttpResult out;
  if (!r) {
    out.error = httplib::to_string(r.error());
    out.not_connected = r.error() == httplib::Error::Connection;
    return out;
  }
  out.status = r->status;
  out.body = std::move(r->body);
  return out;
}

}  // namespace rollwear::api
