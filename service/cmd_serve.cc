// `rollwear serve --db FILE --port N [--config FILE] [--bind ADDR]
//  [--log-level LEVEL] [--threads N]`
// The daemon: opens (creating or migrating) the SQLite database, serves the
// HTTP API of docs/api.md, runs queued and nightly calibrations on one
// background worker, and stops gracefully on SIGINT/SIGTERM (stop accepting,
// finish in-flight requests and the running calibration, close the
// database). Prints the URL it listens on as its first line on stdout.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include "api/http_server.h"
#include "api/router.h"
#include "engine/calibration_runs.h"
#include "engine/diagnosis_jobs.h"
#include "engine/wear_prediction.h"
#include "service/commands.h"
#include "service/config.h"
#include "service/cpu_latency.h"
#include "service/jobs/diagnosis_hooks.h"
#include "service/jobs/job_log.h"
#include "service/jobs/scheduler.h"
#include "storage/db_lock.h"
#include "storage/mill_store.h"

namespace rollwear::cli {
namespace {

// How long the CPU wake-up limit stays held after the last request: long
// enough that a steady stream (one wear read every few seconds) keeps it,
// short enough that an idle daemon lets the CPUs sleep.
constexpr std::chrono::seconds kCpuLatencyReleaseAfter{10};

void SetUpLogging(const std::string& level) {
  auto logger = spdlog::stderr_logger_mt("rollwear");
  logger->set_pattern("%Y-%m-%dT%H:%M:%S.%e%z %l %v");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(level));
  spdlog::flush_on(spdlog::level::info);
}

// Defaults, then the config file, then ROLLWEAR_* variables, then flags.
bool BuildConfig(const ServeArgs& args, service::ServeConfig* config) {
  if (!args.config.empty()) {
    const Status s = service::LoadConfigFile(args.config, config);
    if (!s.ok()) {
      std::fprintf(stderr, "rollwear serve: %s\n", s.message().c_str());
      return false;
    }
  }
  Status s = service::ApplyEnvironment(config);
  for (const auto& [key, value] : args.settings) {
    if (!s.ok()) break;
    std::string flag = "--" + key;
    std::replace(flag.begin(), flag.end(), '_', '-');  // log_level
    s = service::SetConfigValue(key, value, flag, config);
  }
  std::string error;
  if (s.ok() && !config->IsValid(&error)) s = Status::InvalidArgument(error);
  if (!s.ok()) {
    std::fprintf(stderr, "rollwear serve: %s\n", s.message().c_str());
    return false;
  }
  return true;
}

// Blocks SIGINT and SIGTERM in the calling thread (and the threads it starts
// later) and ignores SIGPIPE; returns the set to sigwait on.
sigset_t BlockStopSignals() {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  signal(SIGPIPE, SIG_IGN);
  return stop_signals;
}

// The CPU wake-up latency hold the config asks for (none when the setting is
// negative). False, with the error logged and printed, when it cannot be
// held.
bool HoldCpuLatency(const service::ServeConfig& config,
                    std::unique_ptr<service::CpuLatencyHold>* out) {
  if (config.cpu_wakeup_latency_us < 0) return true;
  StatusOr<std::unique_ptr<service::CpuLatencyHold>> hold =
      service::CpuLatencyHold::Open(config.cpu_wakeup_latency_us,
                                    kCpuLatencyReleaseAfter);
  if (!hold.ok()) {
    spdlog::error("cpu_wakeup_latency_us={}: {}", config.cpu_wakeup_latency_us,
                  hold.status().message());
    std::fprintf(stderr, "rollwear serve: cpu_wakeup_latency_us=%d: %s\n",
                 config.cpu_wakeup_latency_us, hold.status().message().c_str());
    return false;
  }
  *out = std::move(hold).value();
  spdlog::info(
      "cpu wake-up latency limit {} us held while traffic arrives, "
      "released {} s after the last",
      config.cpu_wakeup_latency_us, kCpuLatencyReleaseAfter.count());
  return true;
}

// Opens (creating or migrating) the database; null, with the error logged
// and printed, when it cannot be opened.
std::unique_ptr<storage::MillStore> OpenStore(
    const service::ServeConfig& config) {
  storage::StoreOptions store_options;
  store_options.default_law = config.model;
  store_options.default_option = config.option;
  store_options.wear_limit_um = config.WearLimits();
  StatusOr<std::unique_ptr<storage::MillStore>> opened =
      engine::OpenStore(config.db, store_options);
  if (!opened.ok()) {
    spdlog::error("cannot open database {}: {}", config.db,
                  opened.status().message());
    std::fprintf(stderr, "rollwear serve: %s\n",
                 opened.status().message().c_str());
    return nullptr;
  }
  std::unique_ptr<storage::MillStore> store = std::move(opened).value();
  const storage::StoreCounters counters = store->Counters();
  spdlog::info("database {} open: {} campaigns, {} coils, {} measurements",
               config.db, counters.campaigns, counters.coils,
               counters.measurements);
  return store;
}

// The router's settings from the config: calibrations it queues go to
// `scheduler`, diagnoses to `diagnoses`.
api::ApiOptions ApiOptionsFor(const service::ServeConfig& config,
                              service::Scheduler* scheduler,
                              engine::DiagnosisJobs* diagnoses) {
  api::ApiOptions api_options;
  api_options.token = config.token;
  api_options.body_limit_bytes = config.body_limit_bytes;
  api_options.default_law = config.model;
  api_options.default_option = config.option;
  api_options.on_calibration_queued = [scheduler](int64_t id) {
    service::LogCalibrationQueued(id, "api");
    scheduler->Submit(id);
  };
  api_options.diagnoses = diagnoses;
  return api_options;
}

// The HTTP server's settings from the config, with the request log (at
// debug level) and the CPU latency hold's touch (when one is held).
api::HttpServerOptions HttpOptions(const service::ServeConfig& config,
                                   service::CpuLatencyHold* cpu_latency) {
  api::HttpServerOptions http;
  http.bind_address = config.bind;
  http.port = config.port;
  http.threads = config.threads;
  http.keep_alive_max_count = config.keep_alive_max;
  http.keep_alive_timeout_s = config.keep_alive_timeout_s;
  http.max_connections = config.max_connections;
  http.max_connections_per_client = config.max_connections_per_client;
  http.head_timeout_s = config.head_timeout_s;
  http.body_timeout_s = config.body_timeout_s;
  http.read_timeout_s = config.read_timeout_s;
  http.max_buffered_input_bytes = config.max_buffered_input_bytes;
  // Rate-limited by the server (one line per kind and second).
  http.on_connection_event = [](const api::ConnectionLogEntry& e) {
    spdlog::warn("event={} reason={} remote={} suppressed={}", e.event,
                 e.reason, e.remote_addr, e.suppressed);
  };
  http.payload_max_bytes = config.body_limit_bytes;
  if (spdlog::should_log(spdlog::level::debug)) {
    http.on_request = [](const api::RequestLogEntry& e) {
      spdlog::debug(
          "request method={} path={} status={} ms={:.3f} in={} out={} "
          "remote={}",
          e.method, e.path, e.status, e.seconds * 1e3, e.request_bytes,
          e.response_bytes, e.remote_addr);
    };
  }
  if (cpu_latency != nullptr) {
    // RunServe declares the hold before the server, so it outlives the I/O
    // thread that calls this.
    http.on_activity = [hold = cpu_latency] { hold->Touch(); };
  }
  return http;
}

// Waits for SIGINT or SIGTERM (blocked by BlockStopSignals) and logs it.
void WaitForStopSignal(const sigset_t& stop_signals) {
  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  spdlog::info(
      "received {}, stopping: no new connections, finishing "
      "in-flight requests",
      signal_number == SIGTERM ? "SIGTERM" : "SIGINT");
}

// Each connection is a descriptor: takes the hard limit, and says so when
// even that is below the connection cap.
void RaiseOpenFileLimit(int max_connections) {
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) == 0 &&
      files.rlim_cur < files.rlim_max) {
    files.rlim_cur = files.rlim_max;
    setrlimit(RLIMIT_NOFILE, &files);
  }
  if (files.rlim_cur < static_cast<rlim_t>(max_connections) + 64) {
    spdlog::warn("open file limit {} is below max_connections={} + 64",
                 files.rlim_cur, max_connections);
  }
}

// The nightly recalibration of `config`: when, and which law and option.
service::SchedulerOptions SchedulerOptionsFor(
    const service::ServeConfig& config) {
  service::SchedulerOptions o;
  o.recalibration_minute = config.recalibration_minute;
  o.law = config.model;
  o.option = config.option;
  return o;
}

}  // namespace

int RunServe(const ServeArgs& args) {
  service::ServeConfig config;
  if (!BuildConfig(args, &config)) return 2;
  SetUpLogging(config.log_level);

  // Block the stop signals in every thread (the store's writer, the HTTP
  // pool, the scheduler inherit the mask); the main thread waits for them.
  const sigset_t stop_signals = BlockStopSignals();

  // Opened before the database is touched, so a setting that cannot be
  // honoured stops the start with nothing done.
  std::unique_ptr<service::CpuLatencyHold> cpu_latency;
  if (!HoldCpuLatency(config, &cpu_latency)) return 1;
  // Held until serve returns: `rollwear import` into this database is
  // refused meanwhile (storage/db_lock.h).
  StatusOr<storage::DatabaseLock> db_lock =
      storage::DatabaseLock::Acquire(config.db, "rollwear serve");
  if (!db_lock.ok()) {
    std::fprintf(stderr, "rollwear serve: %s\n",
                 db_lock.status().message().c_str());
    return 1;
  }

  std::unique_ptr<storage::MillStore> store = OpenStore(config);
  if (store == nullptr) return 1;

  api::Router* router_ptr = nullptr;
  // Every calibration run: the scheduler's (API, nightly) and the
  // adoption of a diagnosis.
  const auto on_calibration = [&router_ptr](const storage::CalibrationRecord& r,
                                            double seconds) {
    if (router_ptr != nullptr) {
      router_ptr->metrics()->ObserveCalibration(
          r.status == storage::CalibrationStatus::kDone, seconds);
    }
    service::LogCalibrationFinished(r, seconds);
  };
  engine::CalibrationRuns runs(store.get());
  service::Scheduler scheduler(store.get(), &runs, SchedulerOptionsFor(config),
                               on_calibration);
  engine::DiagnosisJobs diagnoses(
      store.get(), &runs, service::DaemonDiagnosisHooks(on_calibration));

  api::ApiOptions api_options = ApiOptionsFor(config, &scheduler, &diagnoses);
  api_options.build = {args.build.version, args.build.commit};
  api::Router router(store.get(), std::move(api_options));
  router_ptr = &router;

  RaiseOpenFileLimit(config.max_connections);
  api::HttpServer server(&router, HttpOptions(config, cpu_latency.get()));
  const Status started = server.Start();
  if (!started.ok()) {
    spdlog::error("cannot listen: {}", started.message());
    std::fprintf(stderr, "rollwear serve: %s\n", started.message().c_str());
    return 1;
  }
  scheduler.Start();
  const std::string url =
      "http://" + config.bind + ":" + std::to_string(server.port());
  spdlog::info(
      "listening on {} (threads={} keep_alive_max={} body_limit_bytes={} "
      "auth={} nightly={} model={} option={})",
      url, config.threads, config.keep_alive_max, config.body_limit_bytes,
      config.token.empty() ? "off" : "bearer",
      service::FormatTimeOfDay(config.recalibration_minute),
      WearLawName(config.model), config.option);
  std::printf("rollwear: listening on %s\n", url.c_str());
  std::fflush(stdout);

  WaitForStopSignal(stop_signals);
  server.Stop();
  spdlog::info("HTTP server stopped; waiting for the calibration worker");
  scheduler.Stop();
  diagnoses.Stop();
  router_ptr = nullptr;
  store.reset();
  spdlog::info("database closed; bye");
  spdlog::shutdown();
  return 0;
}

}  // namespace rollwear::cli
