#include "tests/e2e/chromium_pipe.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

namespace rollwear::e2e {
namespace {

using json = nlohmann::json;

// The browser's end of the pipe: messages out, messages (and events) in.
class Pipe {
 public:
  Pipe(int to, int from, int timeout_ms)
      : to_(to),
        from_(from),
        deadline_(std::chrono::steady_clock::now() +
                  std::chrono::milliseconds(timeout_ms)) {}

  bool Send(const json& message) {
    const std::string text = message.dump() + std::string(1, '\0');
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = write(to_, text.data() + done, text.size() - done);
      if (n <= 0) return false;
      done += static_cast<size_t>(n);
    }
    return true;
  }

  // The next message, or null at the deadline or end of stream.
  json Next() {
    for (;;) {
      const size_t end = buffer_.find('\0');
      if (end != std::string::npos) {
        json m = json::parse(buffer_.substr(0, end), nullptr, false);
        buffer_.erase(0, end + 1);
        return m;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                            deadline_ - std::chrono::steady_clock::now())
                            .count();
      if (left <= 0) return nullptr;
      pollfd p{from_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char chunk[65536];
      const ssize_t n = read(from_, chunk, sizeof(chunk));
      if (n <= 0) return nullptr;
      buffer_.append(chunk, static_cast<size_t>(n));
    }
  }

  // Sends a command and waits for its answer ("result", or {"error": ...}).
  json Call(int id, const std::string& method, json params = json::object(),
            const std::string& session = "") {
    json message = {{"id", id}, {"method", method}, {"params", params}};
    if (!session.empty()) message["sessionId"] = session;
    if (!Send(message)) return {{"error", method + ": cannot write"}};
    for (;;) {
      json m = Next();
      if (m.is_null()) return {{"error", method + ": no answer in time"}};
      if (!m.contains("id") || m["id"] != id) continue;
      if (m.contains("error"))
        return {{"error", method + ": " + m["error"].dump()}};
      return m.value("result", json::object());
    }
  }

  // Waits for the event `method` of `session`.
  bool WaitFor(const std::string& method, const std::string& session) {
    for (;;) {
      json m = Next();
      if (m.is_null()) return false;
      if (m.value("method", "") == method &&
          m.value("sessionId", "") == session) {
        return true;
      }
    }
  }

 private:
  int to_, from_;
  std::chrono::steady_clock::time_point deadline_;
  std::string buffer_;
};

// Starts the browser with its protocol on fds 3 and 4 of the child; *to and
// *from are this side's ends. Returns the child's pid, or -1.
pid_t Launch(const PageMeasure& m, int* to, int* from) {
  int in[2], out[2];  // in: we write, browser reads; out: the reverse
  if (pipe2(in, O_CLOEXEC) != 0) return -1;
  if (pipe2(out, O_CLOEXEC) != 0) return -1;
  std::vector<std::string> args = {m.chromium,
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
                                   "--window-size=" + std::to_string(m.width) +
                                       "," + std::to_string(m.height),
                                   "about:blank"};
  const pid_t pid = fork();
  if (pid == 0) {
    // Moved above 4 first, so that dup2 cannot overwrite the other end.
    const int r = fcntl(in[0], F_DUPFD, 10), w = fcntl(out[1], F_DUPFD, 10);
    if (r < 0 || w < 0 || dup2(r, 3) != 3 || dup2(w, 4) != 4) _exit(126);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(in[0]);
  close(out[1]);
  if (pid < 0) {
    close(in[1]);
    close(out[0]);
    return -1;
  }
  *to = in[1];
  *from = out[0];
  return pid;
}

json Measure(Pipe* pipe, const PageMeasure& m) {
  json r = pipe->Call(1, "Target.createTarget", {{"url", "about:blank"}});
  if (r.contains("error")) return r;
  const std::string target = r.value("targetId", "");
  r = pipe->Call(2, "Target.attachToTarget",
                 {{"targetId", target}, {"flatten", true}});
  if (r.contains("error")) return r;
  const std::string s = r.value("sessionId", "");
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
  return r["result"].value("value", json());
}

}  // namespace

json MeasureInChromium(const PageMeasure& m) {
  int to = -1, from = -1;
  const pid_t pid = Launch(m, &to, &from);
  if (pid < 0) return {{"error", "cannot start " + m.chromium}};
  Pipe pipe(to, from, m.timeout_ms);
  json value = Measure(&pipe, m);
  pipe.Call(99, "Browser.close");
  close(to);
  close(from);
  int status = 0;
  if (waitpid(pid, &status, WNOHANG) == 0) {
    // Closed pipes end it; give it a moment, then make sure.
    for (int i = 0; i < 50 && waitpid(pid, &status, WNOHANG) == 0; ++i) {
      usleep(100'000);
    }
    if (waitpid(pid, &status, WNOHANG) == 0) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
    }
  }
  return value;
}

}  // namespace rollwear::e2e
