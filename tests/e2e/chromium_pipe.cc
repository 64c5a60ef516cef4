#include "tests/e2e/chromium_pipe.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <deque>
#include <string>
#include <vector>

namespace rollwear::e2e {
namespace {

using json = nlohmann::json;

// A string member of a protocol message, "" when absent or not a string.
std::string Text(const json& m, const char* key) {
  return m.is_object() && m.contains(key) && m[key].is_string()
             ? m[key].get<std::string>()
             : std::string();
}

// The running browser: its process group and this side's pipe ends; the
// destructor closes both ends and ends the whole group, whatever happened.
class Browser {
 public:
  ~Browser() {
    if (to_ >= 0) close(to_);
    if (from_ >= 0) close(from_);
    if (pid_ <= 0) return;
    int status = 0;
    // Closed pipes end it (Browser.close was sent); give it a moment.
    for (int i = 0; i < 50; ++i) {
      if (waitpid(pid_, &status, WNOHANG) != 0) return;
      usleep(100'000);
    }
    kill(-pid_, SIGKILL);  // the group: renderer and GPU helpers too
    waitpid(pid_, &status, 0);
  }

  // Starts `m.chromium` with its protocol on fds 3 (in) and 4 (out) of the
  // child, in its own process group. False when it could not.
  bool Launch(const PageMeasure& m) {
    int in[2], out[2];  // in: we write, the browser reads; out: the reverse
    if (pipe2(in, O_CLOEXEC) != 0) return false;
    if (pipe2(out, O_CLOEXEC) != 0) {
      close(in[0]);
      close(in[1]);
      return false;
    }
    // Everything the child needs is prepared before fork().
    std::vector<std::string> args = {
        m.chromium,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        "--remote-debugging-pipe",
        "--user-data-dir=" + m.profile,
        "--window-size=" + std::to_string(m.width) + "," +
            std::to_string(m.height),
        "about:blank"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
      setpgid(0, 0);
      // Moved above 4 first, so that dup2 cannot overwrite the other end;
      // dup2's copies (3, 4, 1, 2) are not close-on-exec, the rest is.
      const int r = fcntl(in[0], F_DUPFD_CLOEXEC, 10);
      const int w = fcntl(out[1], F_DUPFD_CLOEXEC, 10);
      if (r < 0 || w < 0 || dup2(r, 3) != 3 || dup2(w, 4) != 4) _exit(126);
      const int null = open("/dev/null", O_WRONLY | O_CLOEXEC);
      dup2(null, 1);
      dup2(null, 2);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    to_ = in[1];
    from_ = out[0];
    pid_ = pid;
    return pid > 0;
  }

  int to() const { return to_; }
  int from() const { return from_; }

 private:
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
};

// The protocol over the browser's pipe: commands out, answers and events
// in (events that arrive while a command waits are kept for WaitFor).
class Pipe {
 public:
  Pipe(int to, int from, int timeout_ms)
      : to_(to),
        from_(from),
        deadline_(std::chrono::steady_clock::now() +
                  std::chrono::milliseconds(timeout_ms)) {}

  // Sends a command and waits for its answer ("result", or {"error": ...}).
  json Call(int id, const std::string& method, json params = json::object(),
            const std::string& session = "") {
    json message = {{"id", id}, {"method", method}, {"params", params}};
    if (!session.empty()) message["sessionId"] = session;
    if (!Send(message)) return {{"error", method + ": the browser is gone"}};
    for (;;) {
      json m = Next();
      if (m.is_null()) return {{"error", method + ": no answer in time"}};
      if (!m.is_object()) continue;
      if (!m.contains("id")) {
        events_.push_back(std::move(m));
        continue;
      }
      if (m["id"] != id) continue;
      if (m.contains("error")) {
        return {{"error", method + ": " + m["error"].dump()}};
      }
      return m.contains("result") && m["result"].is_object() ? m["result"]
                                                             : json::object();
    }
  }

  // Waits for the event `method` of `session` (one already received counts).
  bool WaitFor(const std::string& method, const std::string& session) {
    for (;;) {
      json m;
      if (!events_.empty()) {
        m = std::move(events_.front());
        events_.pop_front();
      } else {
        m = Next();
        if (m.is_null()) return false;
      }
      if (Text(m, "method") == method && Text(m, "sessionId") == session) {
        return true;
      }
    }
  }

 private:
  bool Send(const json& message) {
    if (gone_) return false;
    const std::string text = message.dump() + std::string(1, '\0');
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = write(to_, text.data() + done, text.size() - done);
      if (n <= 0) {
        gone_ = true;  // EPIPE (SIGPIPE is ignored while we measure)
        return false;
      }
      done += static_cast<size_t>(n);
    }
    return true;
  }

  // The next message, or null at the deadline or the end of the stream.
  json Next() {
    for (;;) {
      const size_t end = buffer_.find('\0');
      if (end != std::string::npos) {
        json m = json::parse(buffer_.substr(0, end), nullptr, false);
        buffer_.erase(0, end + 1);
        if (m.is_discarded()) continue;
        return m;
      }
      if (gone_) return nullptr;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                            deadline_ - std::chrono::steady_clock::now())
                            .count();
      if (left <= 0) return nullptr;
      pollfd p{from_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char chunk[65536];
      const ssize_t n = read(from_, chunk, sizeof(chunk));
      if (n <= 0) {
        gone_ = true;
        return nullptr;
      }
      buffer_.append(chunk, static_cast<size_t>(n));
    }
  }

  int to_, from_;
  bool gone_ = false;
  std::chrono::steady_clock::time_point deadline_;
  std::string buffer_;
  std::deque<json> events_;
};

json Measure(Pipe* pipe, const PageMeasure& m) {
  json r = pipe->Call(1, "Target.createTarget", {{"url", "about:blank"}});
  if (r.contains("error")) return r;
  const std::string target = Text(r, "targetId");
  r = pipe->Call(2, "Target.attachToTarget",
                 {{"targetId", target}, {"flatten", true}});
  if (r.contains("error")) return r;
  const std::string s = Text(r, "sessionId");
  r = pipe->Call(3, "Emulation.setDeviceMetricsOverride",
                 {{"width", m.width},
                  {"height", m.height},
                  {"deviceScaleFactor", 1},
                  {"mobile", false}},
                 s);
  if (r.contains("error")) return r;
  r = pipe->Call(4, "Page.enable", json::object(), s);
  if (r.contains("error")) return r;
  r = pipe->Call(5, "Page.navigate", {{"url", m.url}}, s);
  if (r.contains("error")) return r;
  if (r.contains("errorText")) return {{"error", "navigate: " + r.dump()}};
  if (!pipe->WaitFor("Page.loadEventFired", s)) {
    return {{"error", "the page did not load in time"}};
  }
  r = pipe->Call(6, "Runtime.evaluate",
                 {{"expression", m.expression}, {"returnByValue", true}}, s);
  if (r.contains("error")) return r;
  if (r.contains("exceptionDetails")) {
    return {{"error", "the expression threw: " + r["exceptionDetails"].dump()}};
  }
  return r.contains("result") && r["result"].is_object()
             ? r["result"].value("value", json())
             : json();
}

}  // namespace

json MeasureInChromium(const PageMeasure& m) {
  // A browser that dies makes our writes fail (EPIPE) instead of killing
  // the test binary with SIGPIPE.
  struct sigaction ignore {
  }, old{};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGPIPE, &ignore, &old);
  json value;
  {
    Browser browser;
    if (!browser.Launch(m)) {
      value = {{"error", "cannot start " + m.chromium}};
    } else {
      Pipe pipe(browser.to(), browser.from(), m.timeout_ms);
      value = Measure(&pipe, m);
      pipe.Call(99, "Browser.close");
    }
  }
  sigaction(SIGPIPE, &old, nullptr);
  return value;
}

}  // namespace rollwear::e2e
