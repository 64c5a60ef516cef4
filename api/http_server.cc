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
//
// This file holds the loop, accepting, the timeout sweep, dispatch and the
// completion queue, and Start/Stop; a connection's reading, parsing and
// writing are in http_connection.cc (shared state: http_server_internal.h).
#include "api/http_server.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <functional>
#include <utility>

#include <malloc.h>

#include "api/codec.h"
#include "api/http_server_internal.h"

namespace rollwear::api {
namespace {

// Router::Handle, with an exception turned into a 500 answer.
HttpResponse SafeHandle(Router* router, const HttpRequest& request,
                        const Router::Routed& routed) {
  try {
    return router->Handle(request, routed);
  } catch (const std::exception& e) {
    return InternalError(e.what());
  } catch (...) {
    return InternalError("unknown exception");
  }
}

}  // namespace

using server_internal::Clock;
using server_internal::Completion;
using server_internal::Conn;
using server_internal::kListenTag;
using server_internal::kSweepMs;
using server_internal::kWakeTag;

Status HttpServer::Impl::Bind() {
  ROLLWEAR_ASSIGN_OR_RETURN(
      listen_fd, ListenOn(options.bind_address, options.port, &port));
  return Status::Ok();
}

void HttpServer::Impl::Run() {
  loop_id = std::this_thread::get_id();
  std::vector<epoll_event> events(256);
  auto next_sweep = Clock::now();
  while (true) {
    ++turn;
    RunReadyTurns();
    const int n =
        epoll_wait(epoll_fd, events.data(), static_cast<int>(events.size()),
                   ready.empty() ? kSweepMs : 0);
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
        Conn* c = Find(tag);
        if (c == nullptr) continue;
        if (events[i].events & EPOLLOUT) {
          Flush(c);
          if (!conns.count(tag)) continue;
          // Requests (or input) held back while answers were pending.
          if (!c->busy && c->out_sent == c->out.size()) Resume(c);
          if (!conns.count(tag)) continue;
        }
        if (events[i].events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR))
          OnReadable(c);
      }
    }
    RunCompletions();
    ResumeBudgetWaiting();
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

bool HttpServer::Impl::Drained() {
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

void HttpServer::Impl::Accept() {
  while (true) {
    if (conns.size() >= static_cast<size_t>(options.max_connections)) {
      // New connections wait in the kernel's backlog until one closes.
      PauseAcceptAtCap();
      return;
    }
    sockaddr_storage addr{};
    socklen_t len = sizeof(addr);
    const int fd = accept4(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len,
                           SOCK_NONBLOCK | SOCK_CLOEXEC);
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
    std::string remote = AddressText(addr);
    if (!AdmitClient(remote)) {
      Refuse(fd, remote);
      continue;
    }
    if (options.tcp_nodelay) {
      int yes = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof(yes));
    }
    auto c = std::make_unique<Conn>(limits);
    c->id = next_id++;
    c->fd = fd;
    c->remote_addr = std::move(remote);
    c->deadline = Clock::now() + std::chrono::seconds(options.head_timeout_s);
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLOUT | EPOLLRDHUP | EPOLLET;
    ev.data.u64 = c->id;
    if (epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &ev) != 0) {
      ReleaseClient(c->remote_addr);
      close(fd);
      continue;
    }
    conns.emplace(c->id, std::move(c));
  }
}

void HttpServer::Impl::Dispatch(Conn* c, HttpRequest request) {
  c->busy = true;
  c->method = request.method;
  c->path = request.path;
  c->request_bytes = request.body.size();
  c->started = Clock::now();
  // Matched once: the route found here is the one Handle answers from.
  Router::Routed routed;
  try {
    routed = router->RouteRequest(request);
  } catch (...) {
    Complete(c, InternalError("routing failed"));
    return;
  }
  const uint64_t id = c->id;
  switch (routed.execution) {
    case Execution::kInline:
      Complete(c, SafeHandle(router, request, routed));
      return;
    case Execution::kAsync:
      ++in_flight;
      try {
        router->HandleAsync(
            request, routed,
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
      pool->Post([this, id, request = std::move(request),
                  routed = std::move(routed)] {
        Post(Completion{id, SafeHandle(router, request, routed)});
      });
      return;
  }
}

void HttpServer::Impl::Post(Completion completion) {
  std::lock_guard<std::mutex> lock(completions_mu);
  completions.push_back(std::move(completion));
  if (std::this_thread::get_id() != loop_id && !wake_pending.exchange(true)) {
    const uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = write(wake_fd, &one, sizeof(one));
  }
}

void HttpServer::Impl::RunCompletions() {
  while (true) {
    {
      std::lock_guard<std::mutex> lock(completions_mu);
      if (completions.empty()) return;
      completions_spare.swap(completions);
    }
    for (Completion& done : completions_spare) {
      --in_flight;
      Conn* c = Find(done.conn_id);
      if (c == nullptr) continue;  // the client went away
      Complete(c, std::move(done.response));
      if (conns.count(done.conn_id)) Resume(c);
    }
    completions_spare.clear();
  }
}

void HttpServer::Impl::Complete(Conn* c, HttpResponse response) {
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
  // glibc raises its mmap threshold after a large mmapped block is freed,
  // so that later request buffers come from the heap and their pages stay
  // with the process after the connection closes. A fixed threshold keeps
  // buffers over 128 KiB mmapped: freeing them gives the memory back.
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  // Fixing it also stops glibc from raising the trim threshold with it;
  // keep up to 1 MiB free at a heap's top rather than trim at every free.
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024);
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
  impl->accept_at_cap = false;
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
