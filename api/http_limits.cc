// The HTTP server's limits (state in http_server_internal.h): connections
// per client address and the cap on all of them, the head and body
// deadlines and the sweep that enforces them, fair turns on the I/O
// thread, the budget of buffered input, the rate-limited connection log,
// and the Date header (RFC 9110 6.6.1) cached once per second.
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>
#include <utility>

#include "api/codec.h"
#include "api/http_server_internal.h"

namespace rollwear::api {

using server_internal::Clock;
using server_internal::Conn;
using server_internal::kBudgetExemptBytes;
using server_internal::kBytesPerTurn;
using server_internal::kKeepBufferBytes;
using server_internal::kListenTag;
using server_internal::kRequestsPerTurn;

namespace server_internal {

void AppendAnswer(std::string* out, const HttpResponse& response,
                  const std::string& date, std::string_view connection,
                  bool with_body) {
  *out += "HTTP/1.1 ";
  *out += std::to_string(response.status);
  *out += ' ';
  *out += ReasonPhrase(response.status);
  *out += "\r\nDate: ";
  *out += date;
  *out += "\r\nContent-Type: ";
  *out += response.content_type;
  *out += "\r\nContent-Length: ";
  *out += std::to_string(response.body.size());
  *out += "\r\n";
  for (const auto& [key, value] : response.headers) {
    *out += key;
    *out += ": ";
    *out += value;
    *out += "\r\n";
  }
  *out += connection;
  *out += "\r\n";
  if (with_body) *out += response.body;
}

}  // namespace server_internal

bool HttpServer::Impl::AdmitClient(const std::string& addr) {
  int& open = per_client[addr];
  if (open >= options.max_connections_per_client) {
    if (open == 0) per_client.erase(addr);
    return false;
  }
  ++open;
  return true;
}

void HttpServer::Impl::ReleaseClient(const std::string& addr) {
  auto it = per_client.find(addr);
  if (it != per_client.end() && --it->second <= 0) per_client.erase(it);
}

void HttpServer::Impl::Refuse(int fd, const std::string& addr) {
  Note(ConnectionEvent::kRefusedPerClient, "connection_refused",
       "per_client_limit", addr);
  HttpResponse r = ProtocolError(
      503, "too many connections from " + addr + " (the limit is " +
               std::to_string(options.max_connections_per_client) +
               "); retry later");
  r.headers.emplace_back("Retry-After", "1");
  std::string out;
  server_internal::AppendAnswer(&out, r, Date(), "Connection: close\r\n", true);
  // A fresh socket's send buffer takes the small answer at once. Drain
  // what the client sent before closing, so the close is a FIN, not a
  // reset that would throw the answer away.
  [[maybe_unused]] const ssize_t n =
      send(fd, out.data(), out.size(), MSG_NOSIGNAL);
  shutdown(fd, SHUT_WR);
  char buf[4096];
  while (recv(fd, buf, sizeof(buf), 0) > 0) {
  }
  close(fd);
}

void HttpServer::Impl::PauseAcceptAtCap() {
  if (accept_at_cap || listen_fd < 0) return;
  epoll_event ev{};
  ev.data.u64 = kListenTag;
  epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &ev);
  accept_at_cap = true;
  Note(ConnectionEvent::kRefusedGlobalCap, "accept_paused", "global_cap", "-");
}

void HttpServer::Impl::ResumeAcceptBelowCap() {
  if (!accept_at_cap ||
      conns.size() >= static_cast<size_t>(options.max_connections)) {
    return;
  }
  accept_at_cap = false;
  if (listen_fd < 0 || accept_paused) return;  // the sweep resumes it
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.u64 = kListenTag;
  epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &ev);
}

void HttpServer::Impl::Note(ConnectionEvent event, const char* log_event,
                            const char* reason, const std::string& remote) {
  router->metrics()->CountConnection(event);
  if (!options.on_connection_event) return;
  const int i = static_cast<int>(event);
  if (last_logged.empty()) {
    last_logged.assign(kNumConnectionEvents, Clock::time_point());
    suppressed.assign(kNumConnectionEvents, 0);
  }
  const auto now = Clock::now();
  if (last_logged[i] != Clock::time_point() &&
      now - last_logged[i] < std::chrono::seconds(1)) {
    ++suppressed[i];
    return;
  }
  last_logged[i] = now;
  try {
    options.on_connection_event(
        ConnectionLogEntry{log_event, reason, remote, suppressed[i]});
  } catch (...) {
  }
  suppressed[i] = 0;
}

void HttpServer::Impl::Sweep(Clock::time_point now) {
  if (accept_paused && now >= accept_resume && listen_fd >= 0) {
    accept_paused = false;
    if (!accept_at_cap) {
      epoll_event ev{};
      ev.events = EPOLLIN;
      ev.data.u64 = kListenTag;
      epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &ev);
    }
  }
  std::vector<Conn*> expired;
  for (auto& [id, c] : conns) {
    if (!c->busy && now > c->deadline) expired.push_back(c.get());
  }
  for (Conn* c : expired) {
    if (c->lingering) {
      // Answered; the drain after "Connection: close" is over.
    } else if (c->out_sent < c->out.size()) {
      Note(ConnectionEvent::kTimeoutWrite, "connection_timeout",
           "write_deadline", c->remote_addr);
    } else if (!c->request_started) {
      Note(ConnectionEvent::kTimeoutIdle, "connection_timeout", "idle",
           c->remote_addr);
    } else if (c->parser.headers_done()) {
      Note(ConnectionEvent::kTimeoutBody, "connection_timeout", "body_deadline",
           c->remote_addr);
    } else {
      Note(ConnectionEvent::kTimeoutHead, "connection_timeout", "head_deadline",
           c->remote_addr);
    }
    Close(c);
  }
}

void HttpServer::Impl::StartHead(Conn* c, Clock::time_point now) {
  c->request_started = true;
  c->phase_deadline = now + std::chrono::seconds(options.head_timeout_s);
}

void HttpServer::Impl::OnProgress(Conn* c, Clock::time_point now) {
  c->deadline = std::min(c->phase_deadline,
                         now + std::chrono::seconds(options.read_timeout_s));
}

bool HttpServer::Impl::TurnOver(Conn* c, bool reading) {
  if (c->turn != turn) {
    c->turn = turn;
    c->turn_requests = 0;
    c->turn_bytes = 0;
  }
  if (reading ? c->turn_bytes < kBytesPerTurn
              : c->turn_requests < kRequestsPerTurn) {
    return false;
  }
  MarkReady(c);
  return true;
}

void HttpServer::Impl::MarkReady(Conn* c) {
  if (c->in_ready) return;
  c->in_ready = true;
  ready.push_back(c->id);
}

Conn* HttpServer::Impl::Find(uint64_t id) {
  auto it = conns.find(id);
  return it == conns.end() ? nullptr : it->second.get();
}

void HttpServer::Impl::Resume(Conn* c) {
  const uint64_t id = c->id;
  if (c->read_pending && !c->budget_waiting) {
    OnReadable(c);
    return;
  }
  ProcessInput(c);
  if (conns.count(id) && c->peer_closed && !c->busy && !c->in_ready &&
      c->out_sent == c->out.size()) {
    Close(c);
  }
}

void HttpServer::Impl::RunReadyTurns() {
  if (ready.empty()) return;
  std::vector<uint64_t> now_ready;
  now_ready.swap(ready);
  for (const uint64_t id : now_ready) {
    Conn* c = Find(id);
    if (c == nullptr) continue;
    c->in_ready = false;
    if (c->busy || c->out_sent < c->out.size()) continue;  // resumed later
    Resume(c);
  }
}

void HttpServer::Impl::AccountInput(Conn* c) {
  if (c->in.empty() && c->in.capacity() > kKeepBufferBytes) {
    std::string().swap(c->in);
  }
  // The bytes received and the body the parser has copied out of them.
  const size_t held = c->in.capacity() + c->parser.request().body.capacity();
  buffered_in += held;
  buffered_in -= c->in_accounted;
  c->in_accounted = held;
}

bool HttpServer::Impl::OverBudget(Conn* c) {
  if (buffered_in < options.max_buffered_input_bytes ||
      c->in.size() - c->in_start < kBudgetExemptBytes) {
    return false;
  }
  if (!c->budget_waiting) {
    c->budget_waiting = true;
    budget_waiting.push_back(c->id);
    Note(ConnectionEvent::kInputBudget, "connection_throttled", "input_budget",
         c->remote_addr);
  }
  return true;
}

void HttpServer::Impl::ResumeBudgetWaiting() {
  if (budget_waiting.empty() ||
      buffered_in >= options.max_buffered_input_bytes) {
    return;
  }
  std::vector<uint64_t> waiting;
  waiting.swap(budget_waiting);
  for (const uint64_t id : waiting) {
    Conn* c = Find(id);
    if (c == nullptr) continue;
    c->budget_waiting = false;
    c->read_pending = true;
    MarkReady(c);
  }
}

const std::string& HttpServer::Impl::Date() {
  const time_t now = time(nullptr);
  if (now == date_second && !date_text.empty()) return date_text;
  static constexpr const char* kDays[] = {"Sun", "Mon", "Tue", "Wed",
                                          "Thu", "Fri", "Sat"};
  static constexpr const char* kMonths[] = {"Jan", "Feb", "Mar", "Apr",
                                            "May", "Jun", "Jul", "Aug",
                                            "Sep", "Oct", "Nov", "Dec"};
  tm t{};
  gmtime_r(&now, &t);
  char text[40];
  std::snprintf(text, sizeof(text), "%s, %02d %s %04d %02d:%02d:%02d GMT",
                kDays[t.tm_wday], t.tm_mday, kMonths[t.tm_mon],
                t.tm_year + 1900, t.tm_hour, t.tm_min, t.tm_sec);
  date_second = now;
  date_text = text;
  return date_text;
}

}  // namespace rollwear::api
