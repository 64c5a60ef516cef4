#include "bench/load_client.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>

#include "api/http_answer.h"

namespace rollwear::bench {
namespace {

using Clock = std::chrono::steady_clock;

double ThreadCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec +
         1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Conn {
  int fd = -1;
  int64_t request = -1;     // in flight; -1 when idle
  int64_t next_paced = -1;  // open loop: this connection's next request
  bool watch_out = false;   // EPOLLOUT requested
  size_t sent = 0;
  Clock::time_point origin;   // latency is measured from here
  Clock::time_point sent_at;  // when the client got to send it
  std::string in;
};

class Loop {
 public:
  Loop(const LoadOptions& o, const std::vector<std::string>& requests)
      : o_(o), requests_(requests) {}

  LoadResult Run() {
    const double cpu0 = ThreadCpuSeconds();
    result_.latency_s.reserve(requests_.size());
    result_.from_send_s.reserve(requests_.size());
    epoll_ = epoll_create1(EPOLL_CLOEXEC);
    timer_ = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u64 = kTimerTag;
    epoll_ctl(epoll_, EPOLL_CTL_ADD, timer_, &ev);
    conns_.resize(std::max(1, o_.connections));
    for (size_t c = 0; c < conns_.size(); ++c) {
      if (!Open(c)) break;
    }
    start_ = Clock::now();
    const auto give_up =
        start_ + std::chrono::duration_cast<Clock::duration>(
                     std::chrono::duration<double>(o_.timeout_s));
    Dispatch();
    epoll_event events[64];
    while (Finished() < static_cast<int64_t>(requests_.size())) {
      if (Clock::now() > give_up) {
        Fail("timed out");
        result_.failures += static_cast<int64_t>(requests_.size()) - Finished();
        break;
      }
      const int n = epoll_wait(epoll_, events, 64, 100);
      for (int i = 0; i < n; ++i) {
        if (events[i].data.u64 == kTimerTag) {
          uint64_t expirations = 0;
          (void)!read(timer_, &expirations, sizeof(expirations));
          continue;
        }
        const size_t c = events[i].data.u64;
        if (events[i].events & EPOLLOUT) Send(c);
        if (events[i].events & (EPOLLIN | EPOLLHUP | EPOLLERR)) Receive(c);
      }
      Dispatch();
    }
    result_.seconds =
        std::chrono::duration<double>(last_answer_ - start_).count();
    for (Conn& conn : conns_) {
      if (conn.fd >= 0) close(conn.fd);
    }
    close(timer_);
    close(epoll_);
    result_.client_cpu_s = ThreadCpuSeconds() - cpu0;
    return std::move(result_);
  }

 private:
  static constexpr uint64_t kTimerTag = ~uint64_t{0};

  int64_t Finished() const { return result_.answered + result_.failures; }

  void Fail(const std::string& why) {
    if (result_.first_error.empty()) result_.first_error = why;
  }

  bool Open(size_t c) {
    Conn& conn = conns_[c];
    conn.fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(o_.port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (conn.fd < 0 || connect(conn.fd, reinterpret_cast<sockaddr*>(&addr),
                               sizeof(addr)) != 0) {
      Fail(std::string("connect: ") + std::strerror(errno));
      if (conn.fd >= 0) close(conn.fd);
      conn.fd = -1;
      return false;
    }
    int one = 1;
    setsockopt(conn.fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    fcntl(conn.fd, F_SETFL, fcntl(conn.fd, F_GETFL) | O_NONBLOCK);
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u64 = c;
    epoll_ctl(epoll_, EPOLL_CTL_ADD, conn.fd, &ev);
    conn.in.clear();
    conn.request = -1;
    conn.watch_out = false;
    return true;
  }

  void Reopen(size_t c) {
    Conn& conn = conns_[c];
    if (conn.fd >= 0) {
      epoll_ctl(epoll_, EPOLL_CTL_DEL, conn.fd, nullptr);
      close(conn.fd);
      conn.fd = -1;
    }
    if (Finished() < static_cast<int64_t>(requests_.size())) Open(c);
  }

  Clock::time_point Due(int64_t i) const {
    return start_ + std::chrono::duration_cast<Clock::duration>(
                        std::chrono::duration<double>(i / o_.rate));
  }

  // Closed loop: idle connections take the next request. Open loop (as
  // wrk2 paces): connection c sends requests c, c + C, c + 2C, ... each at
  // its due time, so every connection carries rate / C requests/s; the
  // timer is armed for the earliest due request of an idle connection.
  void Dispatch() {
    const int64_t n = static_cast<int64_t>(requests_.size());
    const auto now = Clock::now();
    const int64_t num_conns = static_cast<int64_t>(conns_.size());
    Clock::time_point wake = Clock::time_point::max();
    for (size_t c = 0; c < conns_.size(); ++c) {
      Conn& conn = conns_[c];
      if (conn.fd < 0 || conn.request >= 0) continue;
      int64_t i = -1;
      if (o_.rate <= 0) {
        if (next_ >= n) break;
        i = next_++;
      } else {
        if (conn.next_paced < 0) conn.next_paced = static_cast<int64_t>(c);
        if (conn.next_paced >= n) continue;
        if (Due(conn.next_paced) > now) {
          wake = std::min(wake, Due(conn.next_paced));
          continue;
        }
        i = conn.next_paced;
        conn.next_paced += num_conns;
        next_ = std::max(next_, i + 1);
      }
      conn.request = i;
      conn.sent = 0;
      conn.origin = o_.rate > 0 ? Due(i) : now;
      conn.sent_at = now;
      Send(c);
    }
    if (wake != Clock::time_point::max()) {
      const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          wake.time_since_epoch())
                          .count();
      itimerspec spec{};
      spec.it_value.tv_sec = ns / 1000000000;
      spec.it_value.tv_nsec = ns % 1000000000;
      // steady_clock is CLOCK_MONOTONIC on Linux.
      timerfd_settime(timer_, TFD_TIMER_ABSTIME, &spec, nullptr);
    }
  }

  void Send(size_t c) {
    Conn& conn = conns_[c];
    if (conn.request < 0) return;
    const std::string& bytes = requests_[conn.request];
    while (conn.sent < bytes.size()) {
      const ssize_t k = send(conn.fd, bytes.data() + conn.sent,
                             bytes.size() - conn.sent, MSG_NOSIGNAL);
      if (k > 0) {
        conn.sent += static_cast<size_t>(k);
      } else if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        WatchWritable(c, true);
        return;
      } else {
        Lost(c, std::string("send: ") + std::strerror(errno));
        return;
      }
    }
    WatchWritable(c, false);
  }

  // Asks epoll for EPOLLOUT too while a request is only partly sent (one
  // epoll_ctl per change, none per request in the usual case).
  void WatchWritable(size_t c, bool on) {
    Conn& conn = conns_[c];
    if (conn.watch_out == on) return;
    conn.watch_out = on;
    epoll_event ev{};
    ev.events = on ? EPOLLIN | EPOLLOUT : EPOLLIN;
    ev.data.u64 = c;
    epoll_ctl(epoll_, EPOLL_CTL_MOD, conn.fd, &ev);
  }

  // The connection broke: its request (if any) failed; open a new one.
  void Lost(size_t c, const std::string& why) {
    Conn& conn = conns_[c];
    if (conn.request >= 0) {
      ++result_.failures;
      Fail(why);
      conn.request = -1;
    }
    Reopen(c);
  }

  void Receive(size_t c) {
    Conn& conn = conns_[c];
    bool closed = false;
    if (const int err = api::ReadAvailable(conn.fd, &conn.in, &closed)) {
      Lost(c, std::string("recv: ") + std::strerror(err));
      return;
    }
    api::AnswerHead head;
    bool bad = false;
    const bool have_head = api::ParseAnswerHead(conn.in, &head, &bad);
    if (have_head && (bad || conn.request < 0)) {
      Lost(c, "unexpected bytes from the server");
      return;
    }
    if (!have_head || conn.in.size() < head.head_length + head.body_length) {
      if (closed) Lost(c, "connection closed by the server");
      return;
    }
    const auto now = Clock::now();
    last_answer_ = now;
    result_.latency_s.push_back(
        std::chrono::duration<double>(now - conn.origin).count());
    result_.from_send_s.push_back(
        std::chrono::duration<double>(now - conn.sent_at).count());
    ++result_.answered;
    ++result_.statuses[head.status];
    if (o_.expect_status != 0 && head.status != o_.expect_status) {
      ++result_.failures;
      --result_.answered;
      Fail("status " + std::to_string(head.status) + ": " +
           conn.in.substr(head.head_length, 300));
    }
    conn.in.erase(0, head.head_length + head.body_length);
    conn.request = -1;
    if (head.close || closed) Reopen(c);
  }

  const LoadOptions& o_;
  const std::vector<std::string>& requests_;
  std::vector<Conn> conns_;
  int epoll_ = -1, timer_ = -1;
  int64_t next_ = 0;
  Clock::time_point start_, last_answer_;
  LoadResult result_;
};

}  // namespace

std::string RequestBytes(const std::string& method, const std::string& path,
                         const std::string& body) {
  std::string out =
      method + " " + path +
      " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: keep-alive\r\n";
  if (!body.empty() || method == "POST") {
    out += "Content-Type: application/json\r\nContent-Length: " +
           std::to_string(body.size()) + "\r\n";
  }
  out += "\r\n";
  out += body;
  return out;
}

LoadResult RunLoad(const LoadOptions& options,
                   const std::vector<std::string>& requests) {
  return Loop(options, requests).Run();
}

}  // namespace rollwear::bench
