#include "tests/e2e/e2e_util.h"

#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "api/http_client.h"
#include "api/request_encode.h"
#include "core/model/aggregation.h"
#include "core/dataset/dataset_io.h"
#include "core/model/k_structure.h"
#include "core/model/wear_model.h"

#ifndef ROLLWEAR_BINARY
#error "ROLLWEAR_BINARY must name the rollwear executable"
#endif

extern char** environ;

namespace rollwear::e2e {

TempDir::TempDir() {
  char pattern[] = "/tmp/rollwear_e2e_XXXXXX";
  if (mkdtemp(pattern) != nullptr) path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  if (!path_.empty()) std::filesystem::remove_all(path_, ec);
}

Subprocess::Subprocess(const std::vector<std::string>& argv,
                       const std::string& log_path,
                       const std::vector<std::string>& env,
                       const std::string& stderr_path) {
  // Everything the child needs is prepared before fork(): between fork and
  // exec only async-signal-safe calls are allowed.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry = *e;
    const std::string name = entry.substr(0, entry.find('='));
    bool overridden = false;
    for (const std::string& o : env) {
      if (o.compare(0, name.size() + 1, name + "=") == 0) overridden = true;
    }
    if (!overridden) env_strings.push_back(entry);
  }
  for (const std::string& o : env) env_strings.push_back(o);
  std::vector<char*> envp, args;
  for (std::string& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_copy = argv;
  for (std::string& s : argv_copy) args.push_back(s.data());
  args.push_back(nullptr);
  const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  const int err_fd =
      stderr_path.empty()
          ? fd
          : open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);

  pid_ = fork();
  if (pid_ == 0) {
    if (fd >= 0) dup2(fd, STDOUT_FILENO);
    if (err_fd >= 0) dup2(err_fd, STDERR_FILENO);
    const int null_fd = open("/dev/null", O_RDONLY);
    if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
    // Undo signal masks the test runner may have set.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    execve(args[0], args.data(), envp.data());
    _exit(127);
  }
  if (fd >= 0) close(fd);
  if (err_fd >= 0 && err_fd != fd) close(err_fd);
}

Subprocess::~Subprocess() {
  if (pid_ > 0 && !reaped_) {
    kill(pid_, SIGKILL);
    Wait(30);
  }
}

bool Subprocess::Running() {
  if (pid_ <= 0 || reaped_) return false;
  const pid_t r = waitpid(pid_, &status_, WNOHANG);
  if (r == pid_) {
    reaped_ = true;
    return false;
  }
  return true;
}

void Subprocess::Signal(int sig) {
  if (pid_ > 0 && !reaped_) kill(pid_, sig);
}

int Subprocess::Wait(double timeout_s) {
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  while (!reaped_) {
    const pid_t r = waitpid(pid_, &status_, WNOHANG);
    if (r == pid_ || r < 0) {
      reaped_ = true;
      break;
    }
    if (std::chrono::steady_clock::now() > deadline) return -1000;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFEXITED(status_)) return WEXITSTATUS(status_);
  if (WIFSIGNALED(status_)) return -WTERMSIG(status_);
  return -1;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int RunRollwear(const std::vector<std::string>& args, std::string* output,
                double timeout_s) {
  TempDir dir;
  const std::string log = dir / "out.log";
  std::vector<std::string> argv = {ROLLWEAR_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  Subprocess p(argv, log);
  const int code = p.Wait(timeout_s);
  if (output != nullptr) *output = ReadFile(log);
  return code;
}

int RunRollwear(const std::vector<std::string>& args, std::string* out,
                std::string* err, double timeout_s) {
  TempDir dir;
  std::vector<std::string> argv = {ROLLWEAR_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  Subprocess p(argv, dir / "out.log", {}, dir / "err.log");
  const int code = p.Wait(timeout_s);
  *out = ReadFile(dir / "out.log");
  *err = ReadFile(dir / "err.log");
  return code;
}

Daemon::Daemon(std::string db, std::string log_path, int port,
               std::vector<std::string> extra_args,
               std::vector<std::string> env)
    : db_(std::move(db)),
      log_path_(std::move(log_path)),
      port_(port),
      extra_args_(std::move(extra_args)),
      env_(std::move(env)) {}

bool Daemon::Start(std::string* error) {
  const size_t offset = ReadFile(log_path_).size();
  std::vector<std::string> argv = {
      ROLLWEAR_BINARY,       "serve",  "--db",     db_, "--port",
      std::to_string(port_), "--bind", "127.0.0.1"};
  argv.insert(argv.end(), extra_args_.begin(), extra_args_.end());
  process_ = std::make_unique<Subprocess>(argv, log_path_, env_);
  const std::string marker = "rollwear: listening on http://127.0.0.1:";
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    const std::string log = ReadFile(log_path_);
    const size_t at = log.find(marker, offset);
    if (at != std::string::npos) {
      const size_t begin = at + marker.size();
      const size_t end = log.find('\n', begin);
      if (end != std::string::npos) {
        port_ = std::stoi(log.substr(begin, end - begin));
        return true;
      }
    }
    if (!process_->Running()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  *error = "daemon did not start; log:\n" + ReadFile(log_path_).substr(offset);
  return false;
}

void Daemon::Kill9() {
  if (process_) {
    process_->Signal(SIGKILL);
    process_->Wait(30);
  }
}

int Daemon::Terminate() {
  if (!process_) return -1;
  process_->Signal(SIGTERM);
  return process_->Wait(120);
}

int HttpGet(const std::string& url, const std::string& path, json* body) {
  api::HttpClient client(url);
  const api::HttpResult r = client.Get(path);
  if (body != nullptr) *body = json::parse(r.body, nullptr, false);
  return r.status;
}

int HttpPost(const std::string& url, const std::string& path,
             const std::string& body, json* answer, const std::string& token) {
  api::HttpClientOptions options;
  options.token = token;
  api::HttpClient client(url, options);
  const api::HttpResult r = client.Post(path, body);
  if (answer != nullptr) *answer = json::parse(r.body, nullptr, false);
  return r.status;
}

std::map<std::string, double> ScrapeMetrics(const std::string& url) {
  std::map<std::string, double> out;
  api::HttpClient client(url);
  const api::HttpResult r = client.Get("/metrics");
  std::istringstream in(r.body);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.find('{') != std::string::npos) {
      continue;
    }
    const size_t space = line.find(' ');
    if (space == std::string::npos) continue;
    out[line.substr(0, space)] = std::strtod(line.c_str() + space + 1, nullptr);
  }
  return out;
}

bool Simulate(const std::string& dir, int campaigns, int seed,
              std::string* error) {
  std::string output;
  const int code =
      RunRollwear({"simulate", "--out", dir, "--seed", std::to_string(seed),
                   "--campaigns", std::to_string(campaigns)},
                  &output);
  if (code != 0) *error = "rollwear simulate failed:\n" + output;
  return code == 0;
}

std::map<std::string, double> OfflinePrediction(const Dataset& data,
                                                const json& model) {
  std::map<std::string, double> out;
  WearLaw law = WearLaw::kWang;
  ParseWearLaw(model.value("model", "wang"), &law);
  const DatasetIndex index(data);
  StatusOr<WearStatistics> stats = Aggregate(data, index, law);
  if (!stats.ok()) return out;
  StatusOr<KStructure> structure =
      KStructure::ForOption(model.value("option", 1), stats->positions,
                            stats->roll_types, stats->grades);
  if (!structure.ok()) return out;
  WearModel m;
  m.law = law;
  m.structure = *structure;
  const json coefficients = model.value("coefficients", json::object());
  m.k.resize(m.structure.num_coefficients());
  for (int i = 0; i < m.structure.num_coefficients(); ++i) {
    const std::string& name = m.structure.CoefficientName(i);
    m.k[i] = coefficients.contains(name) && coefficients[name].is_number()
                 ? coefficients[name].get<double>()
                 : 1.0;
  }
  if (coefficients.contains("a") && coefficients["a"].is_number()) {
    m.cao_exponent = coefficients["a"].get<double>();
  }
  for (const Observation& obs : stats->observations) {
    const std::string key =
        data.campaigns[obs.campaign].id + "|" +
        RollPositionName(SlotStand(obs.slot), SlotPosition(obs.slot));
    out[key] = PredictObservation(m, *stats, obs);
  }
  return out;
}

json WaitForJob(const std::string& url, const std::string& path, double timeout_s) {
  json body;
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  while (std::chrono::steady_clock::now() < end) {
    if (HttpGet(url, path, &body) != 200) return body;
    if (body["status"] == "done" || body["status"] == "failed") return body;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return body;
}

std::map<std::string, double> WearByKey(const json& wear) {
  std::map<std::string, double> out;
  if (!wear.is_object() || !wear.contains("positions")) return out;
  for (const json& p : wear["positions"]) {
    out[p.value("campaign_id", "") + "|" + p.value("stand", "") + "/" +
        p.value("position", "")] = p.value("predicted_wear_um", 0.0);
  }
  return out;
}

json RollChangeJson(const Dataset& data, int c) {
  std::vector<int> mounts;
  for (size_t i = 0; i < data.mounts.size(); ++i) {
    if (data.mounts[i].campaign == c) mounts.push_back(static_cast<int>(i));
  }
  return json::parse(api::RollChangeRequest(data, c, mounts));
}

json CoilJson(const Dataset& data, int k) {
  std::vector<int> passes;
  for (size_t i = 0; i < data.passes.size(); ++i) {
    if (data.passes[i].coil == k) passes.push_back(static_cast<int>(i));
  }
  if (passes.empty()) return json::object();
  return json::parse(api::CoilRequest(data, passes));
}

std::vector<int> CoilsOf(const Dataset& data, int c) {
  std::map<int, int> by_seq;
  for (const Pass& p : data.passes) {
    if (p.campaign == c) by_seq[p.seq] = p.coil;
  }
  std::vector<int> out;
  for (const auto& [seq, coil] : by_seq) out.push_back(coil);
  return out;
}

}  // namespace rollwear::e2e
