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
// profiles in between go out on N concurrent keep-alive clients. --speed X paces events at X times the
// dataset's own clock (0 = as fast as possible). Connection errors and 5xx
// answers other than 500 are retried for --retry-for seconds: every POST
// has an idempotency key, so a retry of a request whose answer was lost is
// answered 200 and counted once. Two failures stop the replay at once
// (exit 1, the reason on stderr), since no retry can mend them: no
// connection to a daemon that has not answered yet ("is the daemon
// running?"), and a 401 (a missing or wrong token). Prints progress every second, optionally
// the current wear (GET /v1/wear) every --show-wear seconds, and a summary.
// --leave-last-open leaves the last campaign running (no end, no
// measurements, no profiles), so that its rolls stay mounted and GET /v1/wear shows them.
// Exit status 0 only when every event was accepted (2xx).
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/http_client.h"
#include "api/request_encode.h"
#include "core/dataset/dataset_io.h"
#include "service/data_quality_cli.h"
#include "service/commands.h"

namespace rollwear::cli {
namespace {

using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

enum class Kind { kRollChange, kCoil, kEnd, kMeasurement, kProfile };
constexpr int kKinds = 5;

struct Event {
  Kind kind;
  UnixSeconds at;
  // campaign (roll change, end), coil, measurement, or profile (index into
  // Requests' profile groups)
  int index;
};

std::string UrlEncode(const std::string& s) {
  static constexpr const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

// The dataset as requests.
class Requests {
 public:
  explicit Requests(const Dataset& d)
      : d_(d), profiles_(api::ProfileGroups(d)) {
    mounts_of_.resize(d.campaigns.size());
    for (size_t i = 0; i < d.mounts.size(); ++i) {
      mounts_of_[d.mounts[i].campaign].push_back(static_cast<int>(i));
    }
    passes_of_.resize(d.coil_ids.size());
    for (size_t i = 0; i < d.passes.size(); ++i) {
      passes_of_[d.passes[i].coil].push_back(static_cast<int>(i));
    }
  }

  int profiles() const { return static_cast<int>(profiles_.size()); }

  // Events in replay order (see the file comment). With `leave_last_open`
  // the last campaign gets no end and its measurements and profiles are
  // left out.
  std::vector<Event> Timeline(bool leave_last_open) const {
    std::vector<int> order(d_.campaigns.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return d_.campaigns[a].started_at < d_.campaigns[b].started_at;
    });
    std::vector<std::vector<int>> coils_of(d_.campaigns.size());
    for (size_t k = 0; k < passes_of_.size(); ++k) {
      if (passes_of_[k].empty()) continue;
      coils_of[d_.passes[passes_of_[k][0]].campaign].push_back(
          static_cast<int>(k));
    }
    // The grinder's events (measurements, then profiles) by measured_at.
    const std::vector<Event> measured = GrinderEvents();
    std::vector<char> ended(d_.campaigns.size(), 0);
    std::vector<Event> out;
    size_t next_m = 0;
    std::vector<Event> waiting;  // due before their campaign ended
    auto flush = [&](UnixSeconds until) {
      // Grinder events due by `until` whose campaign has ended.
      std::vector<Event> still;
      for (const Event& m : waiting) {
        (ended[CampaignOf(m)] ? out : still).push_back(m);
      }
      waiting.swap(still);
      while (next_m < measured.size() && measured[next_m].at <= until) {
        const Event& m = measured[next_m++];
        (ended[CampaignOf(m)] ? out : waiting).push_back(m);
      }
    };
    for (int c : order) {
      const Campaign& campaign = d_.campaigns[c];
      flush(campaign.started_at);
      out.push_back({Kind::kRollChange, campaign.started_at, c});
      std::vector<int>& coils = coils_of[c];
      std::stable_sort(coils.begin(), coils.end(), [&](int a, int b) {
        return d_.passes[passes_of_[a][0]].seq <
               d_.passes[passes_of_[b][0]].seq;
      });
      for (int k : coils) {
        const UnixSeconds at = d_.passes[passes_of_[k][0]].rolled_at;
        flush(at);
        out.push_back({Kind::kCoil, at, k});
      }
      if (leave_last_open && c == order.back()) break;
      flush(campaign.ended_at);
      out.push_back({Kind::kEnd, campaign.ended_at, c});
      ended[c] = 1;
    }
    flush(INT64_MAX);
    return out;
  }

  std::string Path(const Event& e) const {
    switch (e.kind) {
      case Kind::kRollChange:
        return "/v1/roll-changes";
      case Kind::kCoil:
        return "/v1/coils";
      case Kind::kEnd:
        return "/v1/campaigns/" + UrlEncode(d_.campaigns[e.index].id) + "/end";
      case Kind::kMeasurement:
        return "/v1/measurements";
      case Kind::kProfile:
        return "/v1/profiles";
    }
    return "/";
  }

  std::string Body(const Event& e) const {
    switch (e.kind) {
      case Kind::kRollChange:
        return api::RollChangeRequest(d_, e.index, mounts_of_[e.index]);
      case Kind::kCoil:
        return api::CoilRequest(d_, passes_of_[e.index]);
      case Kind::kEnd:
        return api::CampaignEndRequest(d_, e.index);
      case Kind::kMeasurement:
        return api::MeasurementRequest(d_, e.index);
      case Kind::kProfile:
        return api::ProfileRequest(d_, profiles_[e.index]);
    }
    return "{}";
  }

 private:
  // Measurements and profiles as events, stably sorted by measured_at:
  // measurements in file order, then profiles in the data's order.
  std::vector<Event> GrinderEvents() const {
    std::vector<Event> out;
    for (size_t i = 0; i < d_.measurements.size(); ++i) {
      out.push_back({Kind::kMeasurement, d_.measurements[i].measured_at,
                     static_cast<int>(i)});
    }
    for (size_t i = 0; i < profiles_.size(); ++i) {
      out.push_back({Kind::kProfile,
                     d_.profile_points[profiles_[i].front()].measured_at,
                     static_cast<int>(i)});
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const Event& a, const Event& b) { return a.at < b.at; });
    return out;
  }

  // The campaign of a measurement or profile event.
  int CampaignOf(const Event& e) const {
    return e.kind == Kind::kMeasurement
               ? d_.measurements[e.index].campaign
               : d_.profile_points[profiles_[e.index].front()].campaign;
  }

  const Dataset& d_;
  std::vector<std::vector<int>> mounts_of_;
  std::vector<std::vector<int>> passes_of_;
  std::vector<std::vector<int>> profiles_;  // api::ProfileGroups
};

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
  if (r.status == 401)
    return "401 unauthorized: set --token or ROLLWEAR_TOKEN";
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

// Sends one event, retrying connection errors and 502/503/504; stops the
// replay on a 401 or when no daemon has answered at all.
void Send(const Requests& requests, const Event& e, api::HttpClient* client,
          const ReplayOptions& options, Counters* counters) {
  if (counters->stopped.load()) return;
  const std::string path = requests.Path(e);
  const std::string body = requests.Body(e);
  const auto deadline =
      Clock::now() + std::chrono::milliseconds(
                         static_cast<int64_t>(options.retry_for_s * 1000));
  auto backoff = std::chrono::milliseconds(20);
  api::HttpResult r;
  for (;;) {
    r = client->Post(path, body);
    if (r.answered()) counters->answered.store(true);
    const std::string fatal = FatalReason(r, options.url, *counters);
    if (!fatal.empty()) return Stop(counters, fatal);
    if (counters->stopped.load()) return;
    const bool transient =
        !r.answered() || r.status == 502 || r.status == 503 || r.status == 504;
    if (!transient || Clock::now() >= deadline) break;
    counters->retries.fetch_add(1);
    std::this_thread::sleep_for(backoff);
    backoff = std::min(backoff * 2, std::chrono::milliseconds(500));
  }
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

// N keep-alive clients draining a queue of events that may go in parallel.
class Pool {
 public:
  Pool(int n, const Requests& requests, const ReplayOptions& options,
       Counters* counters) {
    for (int i = 0; i < n; ++i) {
      threads_.emplace_back([this, &requests, &options, counters] {
        api::HttpClientOptions o;
        o.token = options.token;
        api::HttpClient client(options.url, o);
        std::unique_lock<std::mutex> lock(mu_);
        for (;;) {
          cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
          if (queue_.empty()) break;
          const Event e = queue_.front();
          queue_.pop_front();
          ++in_flight_;
          lock.unlock();
          Send(requests, e, &client, options, counters);
          lock.lock();
          --in_flight_;
          if (queue_.empty() && in_flight_ == 0) drained_.notify_all();
        }
      });
    }
  }
  ~Pool() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    for (auto& t : threads_) t.join();
  }
  void Push(const Event& e) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      queue_.push_back(e);
    }
    cv_.notify_one();
  }
  void Drain() {
    std::unique_lock<std::mutex> lock(mu_);
    drained_.wait(lock, [this] { return queue_.empty() && in_flight_ == 0; });
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_, drained_;
  std::deque<Event> queue_;
  int in_flight_ = 0;
  bool stop_ = false;
  std::vector<std::thread> threads_;
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

// Sends the timeline: coils and measurements through the client pool, each
// roll change and campaign end from this thread once the pool is drained;
// paced at `speed` times real time when speed > 0.
void PlayTimeline(const std::vector<Event>& timeline, const Requests& requests,
                  const ReplayOptions& options, int clients, double speed,
                  Clock::time_point start, Counters* counters) {
  Pool pool(clients, requests, options, counters);
  api::HttpClientOptions client_options;
  client_options.token = options.token;
  api::HttpClient main_client(options.url, client_options);
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
      pool.Drain();
      counters->quarter_coils[quarter] = total_coils * (quarter + 1) / 4 -
                                         total_coils * quarter / 4;
      counters->quarter_end_s[quarter++] =
          std::chrono::duration<double>(Clock::now() - start).count();
    }
    if (e.kind == Kind::kCoil) ++pushed_coils;
    if (speed > 0) {
      const auto due =
          start + std::chrono::microseconds(static_cast<int64_t>(
                      static_cast<double>(e.at - t0) / speed * 1e6));
      std::this_thread::sleep_until(due);
    }
    if (e.kind == Kind::kRollChange || e.kind == Kind::kEnd) {
      pool.Drain();
      Send(requests, e, &main_client, options, counters);
    } else {
      pool.Push(e);
    }
  }
  pool.Drain();
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
  const std::vector<Event> timeline =
      requests.Timeline(args.leave_last_open);
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
