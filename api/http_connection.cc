// One connection's I/O on the HTTP server's I/O thread (state in
// http_server_internal.h): reading what the socket has, parsing requests
// and handing them to Dispatch (http_server.cc), writing each answer in
// one send, flushing, and the linger after a "Connection: close" answer.
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "api/codec.h"
#include "api/http_server_internal.h"

namespace rollwear::api {

using server_internal::Clock;
using server_internal::Conn;
using server_internal::kLingerAfterClose;
using server_internal::kMaxPendingOut;

void HttpServer::Impl::Close(Conn* c) {
  epoll_ctl(epoll_fd, EPOLL_CTL_DEL, c->fd, nullptr);
  close(c->fd);
  buffered_in -= c->in_accounted;
  ReleaseClient(c->remote_addr);
  conns.erase(c->id);  // destroys *c
  ResumeAcceptBelowCap();
}

void HttpServer::Impl::OnReadable(Conn* c) {
  const uint64_t id = c->id;
  while (true) {
    ReadSocket(c);
    if (c->lingering) {
      if (c->peer_closed) Close(c);
      return;
    }
    ProcessInput(c);
    if (!conns.count(id)) return;
    if (!c->read_pending || c->busy || c->close_after_write || c->in_ready ||
        c->budget_waiting || c->out.size() - c->out_sent >= kMaxPendingOut) {
      break;
    }
  }
  // A peer that closed its side gets the answers it asked for; then the
  // connection goes.
  if (c->peer_closed && !c->busy && !c->in_ready &&
      c->out_sent == c->out.size()) {
    Close(c);
  }
}

void HttpServer::Impl::ReadSocket(Conn* c) {
  const size_t cap = MaxRequestBytes(limits) + (64 << 10);
  char buf[64 << 10];
  c->read_pending = false;
  while (true) {
    if (!c->lingering && (c->in.size() - c->in_start >= cap || OverBudget(c) ||
                          TurnOver(c, /*reading=*/true))) {
      c->read_pending = true;  // resumed when answered, or its next turn
      break;
    }
    const ssize_t n = recv(c->fd, buf, sizeof(buf), 0);
    if (n > 0) {
      c->turn_bytes += static_cast<size_t>(n);
      if (!c->lingering) {
        c->in.append(buf, static_cast<size_t>(n));
        AccountInput(c);
      }
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    c->peer_closed = true;  // EOF or error
    break;
  }
}

void HttpServer::Impl::ProcessInput(Conn* c) {
  const uint64_t id = c->id;
  ParseRequests(c);
  if (conns.count(id)) AccountInput(c);
}

void HttpServer::Impl::ParseRequests(Conn* c) {
  const uint64_t id = c->id;
  while (conns.count(id) && !c->busy && !c->close_after_write &&
         c->out.size() - c->out_sent < kMaxPendingOut) {
    const std::string_view data = std::string_view(c->in).substr(c->in_start);
    const auto now = Clock::now();
    if (data.empty()) {
      c->in.clear();
      c->in_start = 0;
      return;
    }
    if (TurnOver(c, /*reading=*/false)) return;
    if (!c->request_started) StartHead(c, now);
    const RequestParser::Result result = c->parser.Parse(data);
    if (result == RequestParser::Result::kNeedMore) {
      // Only new bytes push the pause deadline back.
      const bool progress = data.size() > c->parsed_size;
      c->parsed_size = data.size();
      if (c->parser.headers_done()) {
        OnHeadIn(c, now, progress);
      } else if (progress) {
        OnProgress(c, now);
      }
      return;
    }
    if (result == RequestParser::Result::kError) {
      router->metrics()->ObserveRequest(RouteId::kUnmatched,
                                        c->parser.error_status(), 0);
      c->keep_alive = false;
      c->head = false;
      WriteAnswer(c, ProtocolError(c->parser.error_status(),
                                   c->parser.error_message()));
      return;
    }
    c->in_start += c->parser.consumed();
    if (c->in_start == c->in.size()) {
      c->in.clear();
      c->in_start = 0;
    } else if (c->in_start > (64 << 10)) {
      c->in.erase(0, c->in_start);
      c->in_start = 0;
    }
    c->head = c->parser.head();  // before the request is moved out
    c->http10 = c->parser.http10();
    HttpRequest request = std::move(c->parser.request());
    c->keep_alive = c->parser.keep_alive() &&
                    ++c->served < options.keep_alive_max_count &&
                    !stopping.load();
    c->parser.Reset();
    c->request_started = false;
    c->continue_sent = false;
    c->prechecked = false;
    c->parsed_size = 0;
    ++c->turn_requests;
    Dispatch(c, std::move(request));
  }
}

void HttpServer::Impl::OnHeadIn(Conn* c, Clock::time_point now, bool progress) {
  if (!c->prechecked) {
    // The head is in and the body is not: refuse from the head alone
    // (404, 405, 401, 413) before "100 Continue" and before reading the
    // body, then close.
    c->prechecked = true;
    c->phase_deadline = now + std::chrono::seconds(options.body_timeout_s);
    std::optional<HttpResponse> refused;
    try {
      refused = router->PreCheck(c->parser.request());
    } catch (...) {
    }
    if (refused) {
      c->method = c->parser.request().method;
      c->path = c->parser.request().path;
      c->request_bytes = 0;
      c->started = now;
      c->head = c->parser.head();
      c->http10 = c->parser.http10();
      c->keep_alive = false;
      Complete(c, std::move(*refused));
      return;
    }
  }
  if (progress) OnProgress(c, now);
  if (c->parser.expects_continue() && !c->continue_sent) {
    c->continue_sent = true;
    c->out += "HTTP/1.1 100 Continue\r\n\r\n";
    Flush(c);
  }
}

void HttpServer::Impl::WriteAnswer(Conn* c, const HttpResponse& response) {
  std::string& out = c->out;
  if (c->out_sent == out.size()) {
    out.clear();
    c->out_sent = 0;
  }
  if (stopping.load()) c->keep_alive = false;
  std::string connection;
  if (!c->keep_alive) {
    connection = "Connection: close\r\n";
    c->close_after_write = true;
  } else {
    if (c->http10) connection = "Connection: keep-alive\r\n";
    connection +=
        "Keep-Alive: timeout=" + std::to_string(options.keep_alive_timeout_s) +
        "\r\n";
  }
  server_internal::AppendAnswer(&out, response, Date(), connection, !c->head);
  Flush(c);
}

void HttpServer::Impl::Flush(Conn* c) {
  if (c->out_sent == c->out.size()) return;
  while (c->out_sent < c->out.size()) {
    const ssize_t n = send(c->fd, c->out.data() + c->out_sent,
                           c->out.size() - c->out_sent, MSG_NOSIGNAL);
    if (n > 0) {
      c->out_sent += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      c->deadline =
          Clock::now() + std::chrono::seconds(options.write_timeout_s);
      return;  // EPOLLOUT resumes
    }
    Close(c);  // the peer is gone
    return;
  }
  c->out.clear();
  c->out_sent = 0;
  if (c->out.capacity() > server_internal::kKeepBufferBytes) {
    std::string().swap(c->out);
  }
  if (c->close_after_write && !c->lingering) {
    // Shut the write side and drain what the client still sends, so that
    // closing with unread input does not reset the answer away.
    shutdown(c->fd, SHUT_WR);
    c->lingering = true;
    c->in.clear();
    c->in_start = 0;
    AccountInput(c);
    c->deadline = Clock::now() + kLingerAfterClose;
    if (c->peer_closed) {
      Close(c);
      return;
    }
    OnReadable(c);
    return;
  }
  if (!c->busy && !c->lingering && c->in_start == c->in.size()) {
    c->deadline =
        Clock::now() + std::chrono::seconds(options.keep_alive_timeout_s);
  }
}

}  // namespace rollwear::api
