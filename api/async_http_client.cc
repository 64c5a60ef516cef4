#include "api/async_http_client.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <netdb.h>

namespace rollwear::api {
namespace {

using Clock = AsyncHttpClient::Clock;

// host and port of "http://host:port" (port 80 when absent).
bool SplitUrl(const std::string& url, std::string* host, std::string* port) {
  constexpr std::string_view kScheme = "http://";
  if (url.rfind(kScheme, 0) != 0) return false;
  std::string rest = url.substr(kScheme.size());
  rest = rest.substr(0, rest.find('/'));
  if (!rest.empty() && rest.front() == '[') {  // [v6]:port
    const size_t close = rest.find(']');
    if (close == std::string::npos) return false;
    *host = rest.substr(1, close - 1);
    *port = close + 1 < rest.size() && rest[close + 1] == ':'
                ? rest.substr(close + 2)
                : "80";
  } else {
    const size_t colon = rest.rfind(':');
    *host = rest.substr(0, colon);
    *port = colon == std::string::npos ? "80" : rest.substr(colon + 1);
  }
  return !host->empty() && !port->empty();
}

std::string Errno(const char* what, int err) {
  return std::string(what) + ": " + std::strerror(err);
}

struct Queued {
  std::string bytes;  // the whole request
  uint64_t tag = 0;
  Clock::time_point not_before;
  bool resent = false;  // already sent once more after a stale connection
};

struct Conn {
  int fd = -1;
  bool connecting = false;
  bool watch_out = false;
  int answers = 0;        // answers read on this connection
  size_t addr_tried = 0;  // addresses tried for this request's connection
  std::optional<Queued> request;
  size_t sent = 0;
  Clock::time_point deadline;  // connect or answer timeout
  std::string in;
};

}  // namespace

class AsyncHttpClient::Loop {
 public:
  Loop(const std::string& base_url, const AsyncHttpOptions& options, Done done)
      : options_(options), done_(std::move(done)) {
    conns_.resize(std::max(1, options.connections));
    epoll_ = epoll_create1(EPOLL_CLOEXEC);
    if (epoll_ < 0) setup_error_ = Errno("epoll_create1", errno);
    if (!SplitUrl(base_url, &host_, &port_)) {
      setup_error_ = "not an http://host:port URL: " + base_url;
    }
  }

  ~Loop() {
    for (Conn& c : conns_) {
      if (c.fd >= 0) close(c.fd);
    }
    if (epoll_ >= 0) close(epoll_);
  }

  void Post(const std::string& path, const std::string& body, uint64_t tag,
            Clock::time_point not_before) {
    const bool v6 = host_.find(':') != std::string::npos;
    std::string bytes = "POST " + path + " HTTP/1.1\r\nHost: " +
                        (v6 ? "[" + host_ + "]" : host_) + ":" + port_ +
                        "\r\nContent-Type: application/json\r\n";
    if (!options_.token.empty()) {
      bytes += "Authorization: Bearer " + options_.token + "\r\n";
    }
    bytes += "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n";
    bytes += body;
    queue_.push_back(Queued{std::move(bytes), tag, not_before, false});
  }

  void CancelQueued() {
    std::deque<Queued> cancelled;
    cancelled.swap(queue_);
    for (const Queued& q : cancelled)
      done_(q.tag, NoAnswer("cancelled", false));
  }

  size_t pending() const {
    size_t n = queue_.size();
    for (const Conn& c : conns_) n += c.request.has_value() ? 1 : 0;
    return n;
  }

  bool RunUntil(Clock::time_point until) {
    epoll_event events[64];
    for (;;) {
      Dispatch();
      if (pending() == 0) return true;
      const auto now = Clock::now();
      // Past the deadline: one look at what is ready, without waiting.
      const bool last = now >= until;
      const int n =
          epoll_wait(epoll_, events, 64, last ? 0 : WaitMs(now, until));
      for (int i = 0; i < n; ++i) {
        const size_t c = events[i].data.u64;
        if (conns_[c].fd < 0) continue;
        if (events[i].events & EPOLLOUT) Writable(c);
        if (conns_[c].fd >= 0 &&
            (events[i].events & (EPOLLIN | EPOLLHUP | EPOLLERR))) {
          Receive(c);
        }
      }
      ExpireTimeouts();
      if (last) {
        Dispatch();
        return pending() == 0;
      }
    }
  }

 private:
  // Milliseconds epoll may sleep: until `until`, the next queued request's
  // not_before, or a connection's deadline, at most 100 ms.
  int WaitMs(Clock::time_point now, Clock::time_point until) const {
    Clock::time_point wake =
        std::min(until, now + std::chrono::milliseconds(100));
    const bool idle_conn = std::any_of(
        conns_.begin(), conns_.end(), [](const Conn& c) { return !c.request; });
    if (idle_conn) {
      for (const Queued& q : queue_) wake = std::min(wake, q.not_before);
    }
    for (const Conn& c : conns_) {
      if (c.request) wake = std::min(wake, c.deadline);
    }
    const auto ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(wake - now)
            .count();
    return static_cast<int>(std::max<int64_t>(ms, 0) + (wake > now ? 1 : 0));
  }

  // Idle connections take the first queued request that is due.
  void Dispatch() {
    const auto now = Clock::now();
    for (size_t c = 0; c < conns_.size() && !queue_.empty(); ++c) {
      if (conns_[c].request) continue;
      auto it =
          std::find_if(queue_.begin(), queue_.end(),
                       [&](const Queued& q) { return q.not_before <= now; });
      if (it == queue_.end()) return;
      Queued q = std::move(*it);
      queue_.erase(it);
      Start(c, std::move(q));
    }
  }

  void Start(size_t c, Queued q) {
    Conn& conn = conns_[c];
    conn.request = std::move(q);
    conn.sent = 0;
    conn.addr_tried = 0;
    if (conn.fd < 0 && !Open(c)) return;
    if (!conn.connecting) Writable(c);
  }

  // The host's addresses, resolved again whenever none is known (a name
  // that did not resolve may later); "" or the error.
  std::string Resolve() {
    if (!addrs_.empty()) return "";
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const int rc = getaddrinfo(host_.c_str(), port_.c_str(), &hints, &found);
    if (rc != 0 || found == nullptr) {
      return "cannot resolve " + host_ + ": " + gai_strerror(rc);
    }
    for (const addrinfo* a = found; a != nullptr; a = a->ai_next) {
      Address addr;
      std::memcpy(&addr.storage, a->ai_addr, a->ai_addrlen);
      addr.length = a->ai_addrlen;
      addr.family = a->ai_family;
      addrs_.push_back(addr);
    }
    freeaddrinfo(found);
    return "";
  }

  // Opens connection `c` (non-blocking) to the next address not yet tried
  // for its request (the one that last worked first); false when its
  // request has ended.
  bool Open(size_t c) {
    Conn& conn = conns_[c];
    std::string error = setup_error_.empty() ? Resolve() : setup_error_;
    if (!error.empty()) {
      End(c, NoAnswer(error, true));
      return false;
    }
    const Address& addr =
        addrs_[(good_addr_ + conn.addr_tried) % addrs_.size()];
    ++conn.addr_tried;
    conn.fd =
        socket(addr.family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (conn.fd < 0) {
      End(c, NoAnswer(Errno("socket", errno), true));
      return false;
    }
    conn.answers = 0;
    conn.in.clear();
    int one = 1;
    setsockopt(conn.fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    const int rc =
        connect(conn.fd, reinterpret_cast<const sockaddr*>(&addr.storage),
                static_cast<socklen_t>(addr.length));
    if (rc != 0 && errno != EINPROGRESS) return ConnectFailed(c, errno);
    conn.connecting = rc != 0;
    conn.watch_out = conn.connecting;
    conn.deadline =
        Clock::now() + std::chrono::milliseconds(options_.connect_timeout_ms);
    epoll_event ev{};
    ev.events = conn.connecting ? EPOLLIN | EPOLLOUT : EPOLLIN;
    ev.data.u64 = c;
    if (epoll_ctl(epoll_, EPOLL_CTL_ADD, conn.fd, &ev) != 0) {
      const int err = errno;
      Close(c);
      End(c, NoAnswer(Errno("epoll_ctl", err), true));
      return false;
    }
    if (!conn.connecting) Connected(c);
    return true;
  }

  // The connection is made: its address is the one to try first, and the
  // answer's clock starts.
  void Connected(size_t c) {
    Conn& conn = conns_[c];
    conn.connecting = false;
    if (!addrs_.empty()) {
      good_addr_ = (good_addr_ + conn.addr_tried - 1) % addrs_.size();
    }
    conn.deadline =
        Clock::now() + std::chrono::milliseconds(options_.answer_timeout_ms);
  }

  // Connecting failed with `err`: the next address, or the request ends
  // not connected once every address was tried. False when it has ended.
  bool ConnectFailed(size_t c, int err) {
    Conn& conn = conns_[c];
    Close(c);
    if (conn.addr_tried < addrs_.size()) return Open(c);
    addrs_.clear();  // resolved again for the next connection
    good_addr_ = 0;
    End(c, NoAnswer(Errno("connect", err), true));
    return false;
  }

  void Close(size_t c) {
    Conn& conn = conns_[c];
    if (conn.fd >= 0) {
      epoll_ctl(epoll_, EPOLL_CTL_DEL, conn.fd, nullptr);
      close(conn.fd);
    }
    conn.fd = -1;
    conn.connecting = false;
    conn.watch_out = false;
    conn.in.clear();
  }

  static HttpResult NoAnswer(const std::string& why, bool not_connected) {
    HttpResult r;
    r.error = why;
    r.not_connected = not_connected;
    return r;
  }

  // Ends the request of connection `c` with `result`.
  void End(size_t c, HttpResult result) {
    Conn& conn = conns_[c];
    if (!conn.request) return;
    const uint64_t tag = conn.request->tag;
    conn.request.reset();
    done_(tag, result);
  }

  // The connection broke. A request lost on a reused connection before any
  // byte of its answer is sent once more on a new one (the server closed
  // it while idle); otherwise it ends with no answer.
  void Lost(size_t c, const std::string& why) {
    Conn& conn = conns_[c];
    const bool stale = conn.answers > 0 && conn.in.empty() && conn.request &&
                       !conn.request->resent;
    Close(c);
    if (stale) {
      Queued q = std::move(*conn.request);
      conn.request.reset();
      q.resent = true;
      return Start(c, std::move(q));
    }
    End(c, NoAnswer(why, false));
  }

  void Writable(size_t c) {
    Conn& conn = conns_[c];
    if (conn.connecting) {
      int err = 0;
      socklen_t len = sizeof(err);
      getsockopt(conn.fd, SOL_SOCKET, SO_ERROR, &err, &len);
      if (err != 0) {
        // The next address: connected at once, the request goes now.
        if (ConnectFailed(c, err) && !conns_[c].connecting) Writable(c);
        return;
      }
      Connected(c);
    }
    if (!conn.request) return WatchWritable(c, false);
    const std::string& bytes = conn.request->bytes;
    while (conn.sent < bytes.size()) {
      const ssize_t k = send(conn.fd, bytes.data() + conn.sent,
                             bytes.size() - conn.sent, MSG_NOSIGNAL);
      if (k > 0) {
        conn.sent += static_cast<size_t>(k);
      } else if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        return WatchWritable(c, true);
      } else {
        return Lost(c, Errno("send", errno));
      }
    }
    WatchWritable(c, false);
  }

  // Asks epoll for EPOLLOUT too while a request is only partly sent.
  void WatchWritable(size_t c, bool on) {
    Conn& conn = conns_[c];
    if (conn.watch_out == on || conn.fd < 0) return;
    conn.watch_out = on;
    epoll_event ev{};
    ev.events = on ? EPOLLIN | EPOLLOUT : EPOLLIN;
    ev.data.u64 = c;
    epoll_ctl(epoll_, EPOLL_CTL_MOD, conn.fd, &ev);
  }

  void Receive(size_t c) {
    Conn& conn = conns_[c];
    bool closed = false;
    // A read error after a whole answer (a reset behind it) keeps the
    // answer: what was read is parsed first.
    const int err = ReadAvailable(conn.fd, &conn.in, &closed);
    if (err != 0) closed = true;
    const std::string why =
        err != 0 ? Errno("recv", err)
                 : "connection closed by the server before the answer";
    if (conn.in.empty() && !conn.request) {
      if (closed) Close(c);  // the server closed an idle connection
      return;
    }
    AnswerHead head;
    bool bad = false;
    const bool have_head = ParseAnswerHead(conn.in, &head, &bad);
    if (have_head && (bad || !conn.request)) {
      conn.answers = 0;  // not a stale connection: do not send again
      return Lost(c, "unexpected bytes from the server");
    }
    HttpResult r;
    size_t end = 0;
    int complete = 0;
    if (have_head && head.chunked) {
      complete = ChunkedBody(conn.in, head.head_length, &r.body, &end);
    } else if (have_head &&
               conn.in.size() >= head.head_length + head.body_length) {
      r.body = conn.in.substr(head.head_length, head.body_length);
      end = head.head_length + head.body_length;
      complete = 1;
    }
    if (complete < 0) {
      conn.answers = 0;
      return Lost(c, "broken chunked framing from the server");
    }
    if (complete == 0) {
      if (closed) {
        if (!conn.in.empty()) conn.answers = 0;
        Lost(c, why);
      }
      return;
    }
    r.status = head.status;
    conn.in.erase(0, end);
    ++conn.answers;
    if (head.close || closed) Close(c);
    End(c, std::move(r));
  }

  // Ends requests whose connection or answer took too long; a connection
  // that timed out tries the host's next address first.
  void ExpireTimeouts() {
    const auto now = Clock::now();
    for (size_t c = 0; c < conns_.size(); ++c) {
      Conn& conn = conns_[c];
      if (!conn.request || conn.fd < 0 || now < conn.deadline) continue;
      if (conn.connecting) {
        if (ConnectFailed(c, ETIMEDOUT) && !conn.connecting) Writable(c);
        continue;
      }
      Close(c);
      End(c, NoAnswer("answer timed out", false));
    }
  }

  struct Address {
    sockaddr_storage storage{};
    size_t length = 0;
    int family = AF_INET;
  };

  const AsyncHttpOptions options_;
  const Done done_;
  int epoll_ = -1;
  std::string host_, port_;
  std::string setup_error_;  // a bad URL or no epoll: every request fails
  std::vector<Address> addrs_;
  size_t good_addr_ = 0;  // the address that last connected
  std::vector<Conn> conns_;
  std::deque<Queued> queue_;
};

AsyncHttpClient::AsyncHttpClient(const std::string& base_url,
                                 const AsyncHttpOptions& options, Done done)
    : loop_(std::make_unique<Loop>(base_url, options, std::move(done))) {}

AsyncHttpClient::~AsyncHttpClient() = default;

void AsyncHttpClient::Post(const std::string& path, const std::string& body,
                           uint64_t tag, Clock::time_point not_before) {
  loop_->Post(path, body, tag, not_before);
}

void AsyncHttpClient::RunUntilIdle() {
  loop_->RunUntil(Clock::time_point::max());
}

bool AsyncHttpClient::RunUntil(Clock::time_point until) {
  return loop_->RunUntil(until);
}

void AsyncHttpClient::CancelQueued() { loop_->CancelQueued(); }

size_t AsyncHttpClient::pending() const { return loop_->pending(); }

}  // namespace rollwear::api
