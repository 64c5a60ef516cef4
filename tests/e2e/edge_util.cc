#include "tests/e2e/edge_util.h"

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

namespace rollwear::e2e {
namespace {

// Replaces the one occurrence of `from` in *text; false when there is not
// exactly one.
bool ReplaceOnce(std::string* text, const std::string& from,
                 const std::string& to) {
  const size_t at = text->find(from);
  if (at == std::string::npos ||
      text->find(from, at + from.size()) != std::string::npos) {
    return false;
  }
  text->replace(at, from.size(), to);
  return true;
}

// The pids whose parent is `parent` (nginx's workers), from /proc.
std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = ReadFile(entry.path().string() + "/stat");
    const size_t paren = stat.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream rest(stat.substr(paren + 1));
    std::string state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent) out.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return out;
}

}  // namespace

bool EdgeToolPresent(const std::string& path, std::string* fail_message) {
  fail_message->clear();
  if (access(path.c_str(), X_OK) == 0) return true;
  const char* require = std::getenv("ROLLWEAR_REQUIRE_EDGE");
  if (require != nullptr && std::string(require) == "1") {
    *fail_message = path +
                    " is not installed, and ROLLWEAR_REQUIRE_EDGE=1 "
                    "(apt-get install nginx prometheus openssl)";
  }
  return false;
}

int FreeLoopbackPort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return 0;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof(addr);
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
    port = ntohs(addr.sin_port);
  }
  close(fd);
  return port;
}

std::string DeriveEdgeConfig(const std::string& shipped, int daemon_port,
                             int port, int redirect_port,
                             const std::string& cert, const std::string& key,
                             std::string* error) {
  std::string conf = shipped;
  const std::string listen = "listen 127.0.0.1:" + std::to_string(port);
  const bool tls = !cert.empty();
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"server 127.0.0.1:8080 max_conns=512;",
       "server 127.0.0.1:" + std::to_string(daemon_port) + " max_conns=512;"},
      {"listen 80;", "listen 127.0.0.1:" + std::to_string(redirect_port) + ";"},
      {"listen 443 ssl;", tls ? listen + " ssl;" : listen + ";"},
      {"/etc/nginx/tls/rollwear.crt;", cert + ";"},
      {"/etc/nginx/tls/rollwear.key;", key + ";"},
  };
  for (const auto& [from, to] : edits) {
    if (!ReplaceOnce(&conf, from, to)) {
      *error = "deploy/nginx/rollwear.conf has not exactly one '" + from + "'";
      return "";
    }
  }
  if (tls) return conf;
  // Plain HTTP: without the ssl_ lines.
  std::istringstream in(conf);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(' ') != std::string::npos &&
        line.compare(line.find_first_not_of(' '), 4, "ssl_") == 0) {
      continue;
    }
    out += line + "\n";
  }
  return out;
}

EdgeNginx::EdgeNginx(const std::string& dir, const std::string& site)
    : dir_(dir), conf_(dir + "/nginx.conf") {
  std::ofstream(dir + "/rollwear.conf") << site;
  std::ofstream conf(conf_);
  // As root the workers would drop to nobody, who cannot write the
  // temporary folder.
  if (geteuid() == 0) conf << "user root;\n";
  conf << "worker_processes 1;\n"
       << "pid " << dir << "/nginx.pid;\n"
       << "error_log " << dir << "/error.log info;\n"
       << "events { worker_connections 1024; }\n"
       << "http {\n"
       << "  access_log " << dir << "/access.log;\n";
  for (const char* temp : {"client_body", "proxy", "fastcgi", "uwsgi", "scgi"})
    conf << "  " << temp << "_temp_path " << dir << "/" << temp << "_temp;\n";
  conf << "  include " << dir << "/rollwear.conf;\n}\n";
}

EdgeNginx::~EdgeNginx() {
  if (process_ == nullptr || !process_->Running()) return;
  // Fast shutdown: the master stops its workers, reaps them and exits.
  process_->Signal(SIGTERM);
  if (process_->Wait(10) != -1000) return;
  // Stopped, the master cannot start new workers; they would outlive it.
  process_->Signal(SIGSTOP);
  for (pid_t worker : ChildrenOf(process_->pid())) kill(worker, SIGKILL);
  process_->Signal(SIGKILL);
  process_->Wait(30);
}

int EdgeNginx::Test(std::string* output) {
  const std::string log = dir_ + "/nginx-t.log";
  Subprocess t({"/usr/sbin/nginx", "-t", "-p", dir_, "-e", dir_ + "/error.log",
                "-c", conf_},
               log);
  const int code = t.Wait(60);
  *output = ReadFile(log);
  return code;
}

bool EdgeNginx::Start(int port, std::string* error) {
  process_ = std::make_unique<Subprocess>(
      std::vector<std::string>{"/usr/sbin/nginx", "-p", dir_, "-e",
                               dir_ + "/error.log", "-c", conf_, "-g",
                               "daemon off;"},
      dir_ + "/nginx.out");
  const std::string url = "http://127.0.0.1:" + std::to_string(port);
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    json body;
    if (HttpGet(url, "/healthz", &body) != 0) return true;
    if (!process_->Running()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  *error = "nginx did not answer on " + url + ":\n" + ErrorLog() +
           ReadFile(dir_ + "/nginx.out");
  return false;
}

std::string EdgeNginx::ErrorLog() const {
  return ReadFile(dir_ + "/error.log");
}

}  // namespace rollwear::e2e
