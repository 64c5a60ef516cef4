// The daemon's HTTP/1.1 server: one epoll I/O thread plus a small worker
// pool (design notes in http_server.h and docs/architecture.md).
//
// Per connection the I/O thread reads what the socket has (edge-triggered),
// parses one request at a time (api/http_parser.h), and runs it as
// Router::Plan says: in place (wear reads), through the store's group
// commit (coils: the answer comes back from the writer thread through the
// completion queue and an eventfd), or on a worker (everything that may
// wait on SQLite). The answer is written in one send(); a connection's next
// (pipelined) request is parsed only once the answer to the previous one
// is queued, so answers keep their order.
#include "api/http_server.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "api/codec.h"
#include "api/http_parser.h"
#include "api/http_wire.h"

namespace rollwear::api {
namespace {

using Clock = std::chrono::steady_clock;

constexpr uint64_t kListenTag = 0;
constexpr uint64_t kWakeTag = 1;
constexpr uint64_t kFirstConnId = 2;
// Sweep period for timeouts (they are whole seconds).
constexpr int kSweepMs = 100;
// After a "Connection: close" answer the server reads and drops what the
// client still sends (so that closing does not reset the answer away), for
// at most this long.
constexpr auto kLingerAfterClose = std::chrono::seconds(2);
// A client that pipelines requests without reading the answers is not read
// further while this many answer bytes wait for it.
constexpr size_t kMaxPendingOut = 1 << 20;

HttpResponse SafeHandle(Router* router, const HttpRequest& request) {
  try {
    return router->Handle(request);
  } catch (const std::exception& e) {
    return InternalError(e.what());
  } catch (...) {
    return InternalError("unknown exception");
  }
}

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
  int served = 0;
  Clock::time_point deadline;
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

struct Completion {
  uint64_t conn_id;
  HttpResponse response;
};

}  // namespace

struct HttpServer::Impl {
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

  std::unordered_map<uint64_t, std::unique_ptr<Conn>> conns;
  uint64_t next_id = kFirstConnId;
  // Requests with the router or a worker whose answer has not come back.
  int in_flight = 0;

  std::mutex completions_mu;
  std::vector<Completion> completions;
  std::vector<Completion> completions_spare;
  std::atomic<bool> wake_pending{false};

  // ------------------------------------------------------------ setup
  Status Bind() {
    ROLLWEAR_ASSIGN_OR_RETURN(
        listen_fd, ListenOn(options.bind_address, options.port, &port));
    return Status::Ok();
  }

  // ------------------------------------------------------------ loop
  void Run() {
    loop_id = std::this_thread::get_id();
    std::vector<epoll_event> events(256);
    auto next_sweep = Clock::now();
    while (true) {
      const int n = epoll_wait(epoll_fd, events.data(),
                               static_cast<int>(events.size()), kSweepMs);
      if (n > 0 && options.on_activity) options.on_activity();
      for (int i = 0; i < n; ++i) {
        const uint64_t tag = events[i].data.u64;
        if (tag == kListenTag) {
          Accept();
        } else if (tag == kWakeTag) {
          uint64_t count;
          while (read(wake_fd, &count, sizeof(count)) > 0) {
          }
          wake_pending.store(false);
        } else {
          auto it = conns.find(tag);
          if (it == conns.end()) continue;
          Conn* c = it->second.get();
          if (events[i].events & EPOLLOUT) {
            Flush(c);
            if (!conns.count(tag)) continue;
            // Requests (or input) held back while answers were pending.
            if (!c->busy && c->out_sent == c->out.size()) {
              if (c->read_pending) {
                OnReadable(c);
              } else {
                ProcessInput(c);
              }
            }
            if (!conns.count(tag)) continue;
          }
          if (events[i].events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR))
            OnReadable(c);
        }
      }
      RunCompletions();
      const auto now = Clock::now();
      if (now >= next_sweep) {
        Sweep(now);
        next_sweep = now + std::chrono::milliseconds(kSweepMs);
      }
      if (stopping.load() && Drained()) break;
    }
    for (auto& [id, c] : conns) close(c->fd);
    conns.clear();
  }

  // While stopping: stop accepting, close what has nothing in progress.
  bool Drained() {
    if (listen_fd >= 0) {
      epoll_ctl(epoll_fd, EPOLL_CTL_DEL, listen_fd, nullptr);
      close(listen_fd);
      listen_fd = -1;
    }
    std::vector<Conn*> idle;
    for (auto& [id, c] : conns) {
      // A lingering connection closes by itself within kLingerAfterClose.
      if (!c->busy && !c->lingering && c->out_sent == c->out.size()) {
        idle.push_back(c.get());
      }
    }
    for (Conn* c : idle) Close(c);
    return in_flight == 0 && conns.empty();
  }

  void Accept() {
    while (true) {
      sockaddr_storage addr{};
      socklen_t len = sizeof(addr);
      const int fd = accept4(listen_fd, reinterpret_cast<sockaddr*>(&addr),
                             &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS ||
            errno == ENOMEM) {
          // Out of descriptors: stop listening for a moment rather than
          // spin on a level-triggered listener.
          epoll_event ev{};
          ev.data.u64 = kListenTag;
          epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &ev);
          accept_paused = true;
          accept_resume = Clock::now() + std::chrono::milliseconds(100);
        }
        return;
      }
      if (conns.size() >= static_cast<size_t>(options.max_connections)) {
        close(fd);  // the client sees the connection closed; it may retry
        continue;
      }
      if (options.tcp_nodelay) {
        int yes = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof(yes));
      }
      auto c = std::make_unique<Conn>(limits);
      c->id = next_id++;
      c->fd = fd;
      c->remote_addr = AddressText(addr);
      c->deadline = Clock::now() + std::chrono::seconds(options.read_timeout_s);
      epoll_event ev{};
      ev.events = EPOLLIN | EPOLLOUT | EPOLLRDHUP | EPOLLET;
      ev.data.u64 = c->id;
      if (epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &ev) != 0) {
        close(fd);
        continue;
      }
      conns.emplace(c->id, std::move(c));
    }
  }

  void Close(Conn* c) {
    epoll_ctl(epoll_fd, EPOLL_CTL_DEL, c->fd, nullptr);
    close(c->fd);
    conns.erase(c->id);  // destroys *c
  }

  // Reads until the socket is empty (edge-triggered) and parses, again
  // while reading stopped at the input cap and the requests read were
  // answered in place. May close `c`.
  void OnReadable(Conn* c) {
    const uint64_t id = c->id;
    while (true) {
      ReadSocket(c);
      if (c->lingering) {
        if (c->peer_closed) Close(c);
        return;
      }
      ProcessInput(c);
      if (!conns.count(id)) return;
      if (!c->read_pending || c->busy || c->close_after_write ||
          c->out.size() - c->out_sent >= kMaxPendingOut) {
        break;
      }
    }
    // A peer that closed its side gets the answers it asked for; then the
    // connection goes.
    if (c->peer_closed && !c->busy && c->out_sent == c->out.size()) Close(c);
  }

  // Reads what the socket has, up to the input cap (then read_pending).
  void ReadSocket(Conn* c) {
    const size_t cap = MaxRequestBytes(limits) + (64 << 10);
    char buf[64 << 10];
    c->read_pending = false;
    while (true) {
      if (!c->lingering && c->in.size() - c->in_start >= cap) {
        c->read_pending = true;  // resumed when the request is answered
        break;
      }
      const ssize_t n = recv(c->fd, buf, sizeof(buf), 0);
      if (n > 0) {
        if (!c->lingering) c->in.append(buf, static_cast<size_t>(n));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
      c->peer_closed = true;  // EOF or error
      break;
    }
  }

  // Parses and dispatches requests until one is with the router or the
  // input is used up. May close `c`.
  void ProcessInput(Conn* c) {
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
      if (!c->request_started) {
        // The head must arrive within the read timeout of its first byte.
        c->request_started = true;
        c->deadline = now + std::chrono::seconds(options.read_timeout_s);
      }
      const RequestParser::Result result = c->parser.Parse(data);
      if (result == RequestParser::Result::kNeedMore) {
        if (c->parser.headers_done()) {
          c->deadline = now + std::chrono::seconds(options.read_timeout_s);
          if (c->parser.expects_continue() && !c->continue_sent) {
            c->continue_sent = true;
            c->out += "HTTP/1.1 100 Continue\r\n\r\n";
            Flush(c);
          }
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
      Dispatch(c, std::move(request));
    }
  }

  void Dispatch(Conn* c, HttpRequest request) {
    c->busy = true;
    c->method = request.method;
    c->path = request.path;
    c->request_bytes = request.body.size();
    c->started = Clock::now();
    Execution execution = Execution::kBlocking;
    try {
      execution = router->Plan(request);
    } catch (...) {
    }
    const uint64_t id = c->id;
    switch (execution) {
      case Execution::kInline:
        Complete(c, SafeHandle(router, request));
        return;
      case Execution::kAsync:
        ++in_flight;
        try {
          router->HandleAsync(
              request,
              [this, id](HttpResponse response) {
                Post(Completion{id, std::move(response)});
              },
              [this](std::function<void()> task) {
                pool->Post(std::move(task));
              });
        } catch (const std::exception& e) {
          Post(Completion{id, InternalError(e.what())});
        } catch (...) {
          Post(Completion{id, InternalError("unknown exception")});
        }
        return;
      case Execution::kBlocking:
        ++in_flight;
        pool->Post([this, id, request = std::move(request)] {
          Post(Completion{id, SafeHandle(router, request)});
        });
        return;
    }
  }

  // From any thread: hands an answer to the I/O thread.
  // The writer answers a group's coils one after the other; one eventfd
  // write per wake-up of the I/O thread serves them all (a wake-up is the
  // dear part on a virtual machine). The I/O thread clears wake_pending
  // after draining the eventfd and before it takes the queue, so a post it
  // does not take finds the flag clear and writes again. The write is made
  // under the lock: the I/O thread cannot take this completion (and let
  // Stop() free the server) before Post is done with it.
  void Post(Completion completion) {
    std::lock_guard<std::mutex> lock(completions_mu);
    completions.push_back(std::move(completion));
    if (std::this_thread::get_id() != loop_id && !wake_pending.exchange(true)) {
      const uint64_t one = 1;
      [[maybe_unused]] const ssize_t n = write(wake_fd, &one, sizeof(one));
    }
  }

  void RunCompletions() {
    while (true) {
      {
        std::lock_guard<std::mutex> lock(completions_mu);
        if (completions.empty()) return;
        completions_spare.swap(completions);
      }
      for (Completion& done : completions_spare) {
        --in_flight;
        auto it = conns.find(done.conn_id);
        if (it == conns.end()) continue;  // the client went away
        Conn* c = it->second.get();
        Complete(c, std::move(done.response));
        if (!conns.count(done.conn_id)) continue;
        if (c->read_pending) {
          OnReadable(c);
        } else {
          ProcessInput(c);
          if (conns.count(done.conn_id) && c->peer_closed && !c->busy &&
              c->out_sent == c->out.size()) {
            Close(c);
          }
        }
      }
      completions_spare.clear();
    }
  }

  // The router's answer to the request `c` had with it.
  void Complete(Conn* c, HttpResponse response) {
    c->busy = false;
    const double seconds =
        std::chrono::duration<double>(Clock::now() - c->started).count();
    router->metrics()->ObserveRequest(response.route, response.status, seconds);
    if (options.on_request) {
      try {
        options.on_request(
            RequestLogEntry{c->method, c->path, c->remote_addr, response.status,
                            seconds, c->request_bytes, response.body.size()});
      } catch (...) {
      }
    }
    WriteAnswer(c, response);
  }

  // Queues the answer (one send for head and body) and flushes it. May
  // close `c`.
  void WriteAnswer(Conn* c, const HttpResponse& response) {
    std::string& out = c->out;
    if (c->out_sent == out.size()) {
      out.clear();
      c->out_sent = 0;
    }
    out += "HTTP/1.1 ";
    out += std::to_string(response.status);
    out += ' ';
    out += ReasonPhrase(response.status);
    out += "\r\nContent-Type: ";
    out += response.content_type;
    out += "\r\nContent-Length: ";
    out += std::to_string(response.body.size());
    out += "\r\n";
    for (const auto& [key, value] : response.headers) {
      out += key;
      out += ": ";
      out += value;
      out += "\r\n";
    }
    if (stopping.load()) c->keep_alive = false;
    if (!c->keep_alive) {
      out += "Connection: close\r\n";
      c->close_after_write = true;
    } else if (c->http10) {
      out += "Connection: keep-alive\r\n";
    }
    out += "\r\n";
    if (!c->head) out += response.body;
    Flush(c);
  }

  // Sends what is queued. May close `c`.
  void Flush(Conn* c) {
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
    if (c->close_after_write && !c->lingering) {
      // Shut the write side and drain what the client still sends, so that
      // closing with unread input does not reset the answer away.
      shutdown(c->fd, SHUT_WR);
      c->lingering = true;
      c->in.clear();
      c->in_start = 0;
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

  void Sweep(Clock::time_point now) {
    if (accept_paused && now >= accept_resume && listen_fd >= 0) {
      epoll_event ev{};
      ev.events = EPOLLIN;
      ev.data.u64 = kListenTag;
      epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &ev);
      accept_paused = false;
    }
    std::vector<Conn*> expired;
    for (auto& [id, c] : conns) {
      if (!c->busy && now > c->deadline) expired.push_back(c.get());
    }
    for (Conn* c : expired) Close(c);
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
  const HttpServerOptions& o = impl->options;
  impl->limits.max_request_line = 8192;
  impl->limits.max_header_count = o.max_header_count;
  impl->limits.max_header_bytes = o.max_header_bytes;
  impl->limits.max_body_bytes = o.payload_max_bytes;
  ROLLWEAR_RETURN_IF_ERROR(impl->Bind());
  impl->epoll_fd = epoll_create1(EPOLL_CLOEXEC);
  impl->wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (impl->epoll_fd < 0 || impl->wake_fd < 0) {
    return Status::Unavailable(std::string("epoll/eventfd: ") +
                               std::strerror(errno));
  }
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.u64 = kListenTag;
  epoll_ctl(impl->epoll_fd, EPOLL_CTL_ADD, impl->listen_fd, &ev);
  ev.data.u64 = kWakeTag;
  epoll_ctl(impl->epoll_fd, EPOLL_CTL_ADD, impl->wake_fd, &ev);
  impl->pool = std::make_unique<WorkerPool>(o.threads);
  impl->stopping.store(false);
  impl->wake_pending.store(false);
  impl->accept_paused = false;
  impl->loop = std::thread([impl] { impl->Run(); });
  impl->started = true;
  return Status::Ok();
}

int HttpServer::port() const { return impl_->port; }

void HttpServer::Stop() {
  if (!impl_ || !impl_->started) return;
  Impl* impl = impl_.get();
  impl->stopping.store(true);
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = write(impl->wake_fd, &one, sizeof(one));
  if (impl->loop.joinable()) impl->loop.join();
  impl->pool.reset();  // runs what is queued, joins
  if (impl->listen_fd >= 0) close(impl->listen_fd);
  close(impl->epoll_fd);
  close(impl->wake_fd);
  impl->listen_fd = impl->epoll_fd = impl->wake_fd = -1;
  impl->started = false;
}

}  // namespace rollwear::api
