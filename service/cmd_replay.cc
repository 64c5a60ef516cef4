// `rollwear replay --data DIR --url URL [--token T] [--clients N] [--speed X]
//  [--retry-for S] [--show-wear S] [--json FILE] [--leave-last-open]
//  [--quiet]`
// Plays a dataset folder through the HTTP API in time order, as the mill's
// Level 2 system and the roll shop would: for each campaign (by start) the
// roll change, its coils (by seq), the campaign end; each measurement once
// its campaign has ended and its measured_at has come; each grinder profile
// (profiles.csv, when the dataset has one) likewise, after the measurements
// due at the same moment, profiles in the data's order (POST /v1/profiles).
// Roll changes and campaign ends are barriers; coils, measurements and
// profiles in between go out on N concurrent keep-alive connections,
// driven by one thread (api/async_http_client.h). --speed X paces events at
// X times the dataset's own clock (0 = as fast as possible). Connection errors
// and 5xx answers other than 500 are retried for --retry-for seconds: every
// POST has an idempotency key, so a retry of a request whose answer was lost is
// answered 200 and counted once. Two failures stop the replay at once
// (exit 1, the reason on stderr), since no retry can mend them: no
// connection to a daemon that has not answered yet ("is the daemon
// running?"), and a 401 (a missing or wrong token). Prints progress every
// second, optionally the current wear (GET /v1/wear) every --show-wear
// seconds, and a summary. --leave-last-open leaves the last campaign
// running (no end, no measurements, no profiles), so that its rolls stay
// mounted and GET /v1/wear shows them.
// Exit status 0 only when every event was accepted (2xx).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/async_http_client.h"
#include "api/http_client.h"
#include "core/dataset/dataset_io.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"
#include "service/replay_requests.h"

namespace rollwear::cli {
namespace {

using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Counters {
  std::atomic<int64_t> sent[kKinds] = {};      // by Kind: accepted (2xx)
  std::atomic<int64_t> repeated[kKinds] = {};  // of which 200 on a repeat
  std::atomic<int64_t> conflicts{0};
  std::atomic<int64_t> errors{0};
  std::atomic<int64_t> retries{0};
  // Set once the daemon has answered any request: from then on a refused
  // connection is a restart to wait for, not a wrong URL.
  std::atomic<bool> answered{false};
  // Set by Stop(): every further event is skipped.
  std::atomic<bool> stopped{false};
  std::mutex print_mu;
  int printed_errors = 0;
  std::string stop_reason;  // guarded by print_mu
  // When each quarter of the timeline's coils had been answered (s from the
  // start, the first quarter with the clients' connecting) and its coils;
  // 0 if not reached or < 4 coils. Written by the timeline's thread only.
  double quarter_end_s[4] = {};
  int64_t quarter_coils[4] = {};
};

// Stops the replay with `reason` (the first reason wins).
void Stop(Counters* counters, const std::string& reason) {
  std::lock_guard<std::mutex> lock(counters->print_mu);
  if (counters->stopped.exchange(true)) return;
  counters->stop_reason = reason;
}

// The reason to stop the replay at once for this result, or "".
std::string FatalReason(const api::HttpResult& r, const std::string& url,
                        const Counters& counters) {
  if (r.status == 401) return "401 unauthorized: set --token or ROLLWEAR_TOKEN";
  if (r.not_connected && !counters.answered.load())
    return "connection refused at " + url + ": is the daemon running? (" +
           r.error + ")";
  return "";
}

struct ReplayOptions {
  std::string url;
  std::string token;
  double retry_for_s = 60;
};

// Whether a request may be sent again: no answer, or 502/503/504.
bool Transient(const api::HttpResult& r) {
  return !r.answered() || r.status == 502 || r.status == 503 || r.status == 504;
}

// Counts the final result of one event (and prints the first ten
// failures).
void Count(const Event& e, const std::string& path, const api::HttpResult& r,
           Counters* counters) {
  const int k = static_cast<int>(e.kind);
  if (r.status >= 200 && r.status < 300) {
    counters->sent[k].fetch_add(1);
    if (r.status == 200 && e.kind != Kind::kEnd)
      counters->repeated[k].fetch_add(1);
    return;
  }
  (r.status == 409 ? counters->conflicts : counters->errors).fetch_add(1);
  std::lock_guard<std::mutex> lock(counters->print_mu);
  if (counters->printed_errors++ < 10) {
    std::fprintf(stderr, "replay: POST %s -> %s\n", path.c_str(),
                 r.answered()
                     ? (std::to_string(r.status) + " " + r.body).c_str()
                     : ("no answer: " + r.error).c_str());
  }
}

// Sends events over N keep-alive connections driven by one thread
// (api/async_http_client.h), retrying connection errors and 502/503/504
// with a doubling backoff (20 ms to 500 ms) for --retry-for seconds;
// stops the replay on a 401 or when no daemon has answered at all.
class Sender {
 public:
  Sender(int clients, const Requests& requests, const ReplayOptions& options,
         Counters* counters)
      : requests_(requests),
        options_(options),
        counters_(counters),
        client_(options.url, ClientOptions(options, clients),
                [this](uint64_t tag, const api::HttpResult& r) {
                  OnResult(tag, r);
                }) {}

  // Queues `e` (nothing once the replay has stopped).
  void Push(const Event& e) {
    if (counters_->stopped.load()) return;
    const uint64_t tag = next_tag_++;
    Attempt& a = attempts_[tag];
    a.event = e;
    a.path = requests_.Path(e);
    a.body = requests_.Body(e);
    client_.Post(a.path, a.body, tag);
  }
  // Sends until every pushed event has its final answer.
  void Drain() { client_.RunUntilIdle(); }
  // Sends until `until` (or until drained).
  void RunUntil(Clock::time_point until) { client_.RunUntil(until); }

 private:
  struct Attempt {
    Event event{};
    std::string path, body;
    // --retry-for from the first failure (time queued behind the others
    // does not count).
    std::optional<Clock::time_point> deadline;
    std::chrono::milliseconds backoff{20};
  };

  static api::AsyncHttpOptions ClientOptions(const ReplayOptions& options,
                                             int clients) {
    api::AsyncHttpOptions o;
    o.token = options.token;
    o.connections = std::max(1, clients);
    return o;
  }

  void OnResult(uint64_t tag, const api::HttpResult& r) {
    auto it = attempts_.find(tag);
    if (it == attempts_.end()) return;
    Attempt& a = it->second;
    if (r.answered()) counters_->answered.store(true);
    const std::string fatal = FatalReason(r, options_.url, *counters_);
    if (!fatal.empty()) Stop(counters_, fatal);
    if (counters_->stopped.load()) {
      // Nothing more is sent: what is queued ends here uncounted, as the
      // old pool skipped it.
      attempts_.erase(it);
      client_.CancelQueued();
      return;
    }
    const auto now = Clock::now();
    if (Transient(r) && !a.deadline) {
      a.deadline = now + std::chrono::milliseconds(
                             static_cast<int64_t>(options_.retry_for_s * 1000));
    }
    if (Transient(r) && now < *a.deadline) {
      counters_->retries.fetch_add(1);
      client_.Post(a.path, a.body, tag, now + a.backoff);
      a.backoff = std::min(a.backoff * 2, std::chrono::milliseconds(500));
      return;
    }
    Count(a.event, a.path, r, counters_);
    attempts_.erase(it);
  }

  const Requests& requests_;
  const ReplayOptions& options_;
  Counters* const counters_;
  std::unordered_map<uint64_t, Attempt> attempts_;
  uint64_t next_tag_ = 0;
  api::AsyncHttpClient client_;
};

void PrintWear(const std::string& url, double elapsed) {
  api::HttpClient client(url);
  const api::HttpResult r = client.Get("/v1/wear");
  if (r.status != 200) return;
  const Json j = Json::parse(r.body, nullptr, false);
  if (j.is_discarded() || !j.contains("positions")) return;
  std::printf("  wear at %5.1f s (model v%s):", elapsed,
              j.value("model_version", Json(0)).dump().c_str());
  for (const Json& p : j["positions"]) {
    const Json interval = p.value("interval_um", Json::array({0, 0}));
    std::printf("  %s/%s %s %.1f um [%.0f-%.0f] after %d coils",
                p.value("stand", "").c_str(), p.value("position", "").c_str(),
                p.value("campaign_id", "").c_str(),
                p.value("predicted_wear_um", 0.0),
                interval.size() == 2 ? interval[0].get<double>() : 0.0,
                interval.size() == 2 ? interval[1].get<double>() : 0.0,
                p.value("coils", 0));
  }
  std::printf("\n");
  std::fflush(stdout);
}

// The replay's settings from the flags (and ROLLWEAR_TOKEN); false, with
// the message printed, when --url is not an http:// URL.
bool ReplayOptionsFrom(const ReplayArgs& args, ReplayOptions* options) {
  options->url = args.url;
  options->token = args.token;
  options->retry_for_s = args.retry_for_s;
  if (options->token.empty() && std::getenv("ROLLWEAR_TOKEN") != nullptr) {
    options->token = std::getenv("ROLLWEAR_TOKEN");
  }
  if (options->url.rfind("http://", 0) != 0) {
    std::fprintf(stderr, "rollwear replay: --url must start with http://\n");
    return false;
  }
  while (!options->url.empty() && options->url.back() == '/')
    options->url.pop_back();
  return true;
}

// The reporter thread's loop until `done`: a progress line every second
// (unless quiet) and the wear every `show_wear` seconds (when > 0).
void ReportWhileRunning(Clock::time_point start, int64_t total_coils,
                        double show_wear, bool quiet, const std::string& url,
                        const Counters& counters,
                        const std::atomic<bool>& done) {
  auto next_progress = start + std::chrono::seconds(1);
  auto next_wear =
      start + std::chrono::milliseconds(static_cast<int64_t>(show_wear * 1000));
  while (!done.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start).count();
    if (!quiet && now >= next_progress) {
      next_progress += std::chrono::seconds(1);
      const int64_t coils = counters.sent[1].load();
      std::printf(
          "  %5.1f s: %lld/%lld coils (%.0f coils/s), %lld "
          "campaigns, %lld measurements, %lld retries\n",
          elapsed, static_cast<long long>(coils),
          static_cast<long long>(total_coils),
          elapsed > 0 ? coils / elapsed : 0.0,
          static_cast<long long>(counters.sent[0].load()),
          static_cast<long long>(counters.sent[3].load()),
          static_cast<long long>(counters.retries.load()));
      std::fflush(stdout);
    }
    if (show_wear > 0 && now >= next_wear) {
      next_wear +=
          std::chrono::milliseconds(static_cast<int64_t>(show_wear * 1000));
      PrintWear(url, elapsed);
    }
  }
}

// Sends the timeline: coils, measurements and profiles go out together;
// each roll change and campaign end alone, once everything before it has
// its answer; paced at `speed` times real time when speed > 0.
void PlayTimeline(const std::vector<Event>& timeline, const Requests& requests,
                  const ReplayOptions& options, int clients, double speed,
                  Clock::time_point start, Counters* counters) {
  Sender sender(clients, requests, options, counters);
  const UnixSeconds t0 = timeline.empty() ? 0 : timeline.front().at;
  const auto total_coils = static_cast<int64_t>(
      std::count_if(timeline.begin(), timeline.end(),
                    [](const Event& e) { return e.kind == Kind::kCoil; }));
  int64_t pushed_coils = 0;
  int quarter = 0;
  for (const Event& e : timeline) {
    if (counters->stopped.load()) break;
    // A quarter of the coils sent: wait for their answers and note the time.
    while (quarter < 4 && total_coils >= 4 &&
           pushed_coils >= total_coils * (quarter + 1) / 4) {
      sender.Drain();
      counters->quarter_coils[quarter] =
          total_coils * (quarter + 1) / 4 - total_coils * quarter / 4;
      counters->quarter_end_s[quarter++] =
          std::chrono::duration<double>(Clock::now() - start).count();
    }
    if (e.kind == Kind::kCoil) ++pushed_coils;
    if (speed > 0) {
      const auto due =
          start + std::chrono::microseconds(static_cast<int64_t>(
                      static_cast<double>(e.at - t0) / speed * 1e6));
      sender.RunUntil(due);
      std::this_thread::sleep_until(due);
    }
    const bool barrier = e.kind == Kind::kRollChange || e.kind == Kind::kEnd;
    if (barrier) sender.Drain();
    sender.Push(e);
    if (barrier) sender.Drain();
  }
  sender.Drain();
  if (quarter == 3 && total_coils >= 4 && !counters->stopped.load()) {
    counters->quarter_coils[3] = total_coils - total_coils * 3 / 4;
    counters->quarter_end_s[3] =
        std::chrono::duration<double>(Clock::now() - start).count();
  }
}

// Coils per second in each quarter of the timeline's coils (null for a
// quarter the replay did not finish).
Json QuarterRates(const Counters& counters) {
  Json rates = Json::array();
  double from = 0;
  for (int q = 0; q < 4; ++q) {
    const double to = counters.quarter_end_s[q];
    const int64_t coils = counters.quarter_coils[q];
    rates.push_back(coils > 0 && to > from
                        ? Json(static_cast<double>(coils) / (to - from))
                        : Json());
    from = to;
  }
  return rates;
}

// The closing summary line, and the summary as JSON into `json_path` (when
// not empty).
void PrintSummary(const Counters& counters, double seconds,
                  const std::string& json_path) {
  const int64_t coils = counters.sent[1].load();
  const double rate = seconds > 0 ? coils / seconds : 0;
  std::printf(
      "replay: %lld coils (%lld repeated), %lld roll changes, %lld campaign "
      "ends, %lld measurements, %lld profiles in %.2f s: %.0f coils/s; %lld "
      "conflicts, %lld errors, %lld retries\n",
      static_cast<long long>(coils),
      static_cast<long long>(counters.repeated[1].load()),
      static_cast<long long>(counters.sent[0].load()),
      static_cast<long long>(counters.sent[2].load()),
      static_cast<long long>(counters.sent[3].load()),
      static_cast<long long>(counters.sent[4].load()), seconds, rate,
      static_cast<long long>(counters.conflicts.load()),
      static_cast<long long>(counters.errors.load()),
      static_cast<long long>(counters.retries.load()));
  std::fflush(stdout);
  if (!json_path.empty()) {
    const Json summary{{"coils", coils},
                       {"coils_repeated", counters.repeated[1].load()},
                       {"roll_changes", counters.sent[0].load()},
                       {"campaign_ends", counters.sent[2].load()},
                       {"measurements", counters.sent[3].load()},
                       {"profiles", counters.sent[4].load()},
                       {"conflicts", counters.conflicts.load()},
                       {"errors", counters.errors.load()},
                       {"retries", counters.retries.load()},
                       {"seconds", seconds},
                       {"coils_per_second", rate},
                       {"coils_per_second_by_quarter", QuarterRates(counters)}};
    std::ofstream out(json_path);
    out << summary.dump(2) << "\n";
  }
}

}  // namespace

int RunReplay(const ReplayArgs& args) {
  const long long clients = args.clients;
  const double speed = args.speed, show_wear = args.show_wear_s;
  ReplayOptions options;
  if (!ReplayOptionsFrom(args, &options)) return 2;
  signal(SIGPIPE, SIG_IGN);
  // Whether a daemon answers before the (possibly long) read of the data:
  // if it does, a refused connection later is a restart to wait for
  // (--retry-for), even before the first POST was answered.
  const bool reached = [&options] {
    api::HttpClient probe(options.url);
    return probe.Get("/healthz").answered();
  }();

  Dataset data;
  if (int code = ReadDatasetForTool("replay", args.data, &data)) return code;
  const Requests requests(data);
  const std::vector<Event> timeline = requests.Timeline(args.leave_last_open);
  const bool quiet = args.quiet;
  const auto total_coils = static_cast<int64_t>(data.coil_ids.size());
  if (!quiet) {
    std::printf(
        "replay: %zu campaigns, %lld coils, %zu measurements, %d profiles "
        "-> %s with %lld clients%s\n",
        data.campaigns.size(), static_cast<long long>(total_coils),
        data.measurements.size(), requests.profiles(), options.url.c_str(),
        clients,
        speed > 0 ? (", speed x" + std::to_string(speed)).c_str()
                  : ", as fast as possible");
    std::fflush(stdout);
  }

  Counters counters;
  counters.answered.store(reached);
  const auto start = Clock::now();
  std::atomic<bool> done{false};
  std::thread reporter([&] {
    ReportWhileRunning(start, total_coils, show_wear, quiet, options.url,
                       counters, done);
  });
  PlayTimeline(timeline, requests, options, static_cast<int>(clients), speed,
               start, &counters);
  const double seconds =
      std::chrono::duration<double>(Clock::now() - start).count();
  done.store(true);
  reporter.join();
  if (show_wear > 0) PrintWear(options.url, seconds);
  PrintSummary(counters, seconds, args.json);
  if (counters.stopped.load()) {
    std::lock_guard<std::mutex> lock(counters.print_mu);
    std::fprintf(stderr, "rollwear replay: stopped: %s\n",
                 counters.stop_reason.c_str());
    return 1;
  }
  return counters.conflicts.load() == 0 && counters.errors.load() == 0 ? 0 : 1;
}

}  // namespace rollwear::cli
