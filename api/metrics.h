// Metrics: the daemon's Prometheus figures and their text exposition
// (format 0.0.4) for GET /metrics.
//
//   rollwear_http_request_duration_seconds{route,method}  histogram
//   rollwear_http_requests_total{route,method,code}        counter
//   rollwear_coils_ingested_total                          counter
//   rollwear_http_connections_total{event}                 counter
//   rollwear_calibration_runs_total{status}                counter
//   rollwear_calibration_duration_seconds                  histogram
//   rollwear_build_info{version,commit}                    gauge, 1
// plus figures read from the store at scrape time (StoreFigures):
//   rollwear_group_commits_total, rollwear_validation_gap_um,
//   rollwear_model_version, rollwear_{coils,campaigns,measurements}_stored,
//   rollwear_measurements_since_last_calibration,
//   rollwear_measurements_suspect_stored, rollwear_up,
//   rollwear_predicted_wear_um{stand,position},
// and the process_* figures of /proc/self (api/process_metrics.h).
// Label rules: `route` is a route template or "unmatched", never "";
// `method` is the request's own method (GET, HEAD, POST, PUT, DELETE,
// PATCH, OPTIONS, or OTHER for any other and for requests refused before
// their request line was read); `code` is the exact status code ("other"
// once the table of codes seen is full).
//
// Thread-safety: all methods are thread-safe; the hot path (Observe*,
// CountCoil) is lock-free (relaxed atomics, and a compare-and-swap the
// first time a status code is seen on a route and method).
#ifndef ROLLWEAR_API_METRICS_H_
#define ROLLWEAR_API_METRICS_H_

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/routes.h"
#include "engine/wear_answers.h"
#include "storage/store_types.h"

namespace rollwear::api {

// "/v1/wear/{stand}/{position}".
const char* RoutePath(RouteId route);
// "GET" or "POST" ("" for kUnmatched).
const char* RouteMethod(RouteId route);

// The method label of the request metrics.
enum class HttpMethod : int {
  kGet = 0,
  kHead,
  kPost,
  kPut,
  kDelete,
  kPatch,
  kOptions,
  kOther,  // any other method, or none read
  kCount
};
constexpr int kNumMethods = static_cast<int>(HttpMethod::kCount);
// kOther for anything but the seven names (case-sensitive, RFC 9110 9.1).
HttpMethod ParseHttpMethod(std::string_view method);
// "GET" ... "OPTIONS", "OTHER".
const char* HttpMethodName(HttpMethod method);

// The labels of one answered request: the route that answered and the
// request's method. From a bare RouteId (implicit, for answers given
// before routing), the method is the route's own, or kOther for
// kUnmatched.
struct RequestLabels {
  RouteId route_id = RouteId::kUnmatched;
  HttpMethod method = HttpMethod::kOther;

  RequestLabels() = default;
  RequestLabels(RouteId route);  // NOLINT(google-explicit-constructor)
  RequestLabels(RouteId route, HttpMethod method)
      : route_id(route), method(method) {}
  bool operator==(RouteId route) const { return route_id == route; }
};

// What GET /metrics says of the build (rollwear_build_info).
struct BuildInfo {
  std::string version;  // "1.4.0"
  std::string commit;   // git commit of the build, or "unknown"
};

// What the HTTP server did to a connection outside of answering requests
// (the event label of rollwear_http_connections_total).
enum class ConnectionEvent : int {
  kRefusedGlobalCap = 0,  // at the connection cap: accepting paused
  kRefusedPerClient,      // over the per-client limit: 503 and closed
  kTimeoutHead,           // head not in within head_timeout
  kTimeoutBody,           // body not in within body_timeout (or paused)
  kTimeoutIdle,           // kept-alive and idle past keep_alive_timeout
  kTimeoutWrite,          // answer not taken within write_timeout
  kInputBudget,           // not read: total buffered input over budget
  kCount
};
constexpr int kNumConnectionEvents = static_cast<int>(ConnectionEvent::kCount);
// "refused_global_cap", "timeout_head", ...
const char* ConnectionEventName(ConnectionEvent event);

// Figures read from the store when /metrics is scraped.
struct StoreFigures {
  bool healthy = false;
  storage::StoreCounters counters;
  int64_t model_version = 0;
  double validation_gap_um = 0;  // NaN when the active model has none
  // Predicted wear of each mounted roll position (GET /v1/wear).
  std::vector<engine::PositionWear> wear;
};

class Metrics {
 public:
  explicit Metrics(BuildInfo build = {}) : build_(std::move(build)) {}
  Metrics(const Metrics&) = delete;
  Metrics& operator=(const Metrics&) = delete;

  // One answered request: latency from the request read to the answer
  // ready, and its status code (100..599; others count as code "other").
  void ObserveRequest(RequestLabels labels, int status, double seconds);
  // One coil newly stored through the API (repeats are not counted).
  void CountCoilIngested() {
    coils_ingested_.fetch_add(1, std::memory_order_relaxed);
  }
  // One refused, timed-out or throttled connection.
  void CountConnection(ConnectionEvent event) {
    connections_[static_cast<int>(event)].fetch_add(1,
                                                    std::memory_order_relaxed);
  }
  // One finished calibration run ("done" or "failed") and its duration.
  void ObserveCalibration(bool succeeded, double seconds);

  int64_t coils_ingested() const {
    return coils_ingested_.load(std::memory_order_relaxed);
  }

  // The Prometheus text exposition of everything above.
  std::string Render(const StoreFigures& store) const;

 private:
  // Cumulative-bucket histogram with fixed upper bounds.
  template <size_t N>
  struct Histogram {
    std::array<std::atomic<uint64_t>, N> buckets{};  // count per bucket
    std::atomic<uint64_t> count{0};
    std::atomic<uint64_t> sum_ns{0};
    void Observe(const std::array<double, N>& bounds, double seconds);
    void Render(std::string_view name, std::string_view labels,
                const std::array<double, N>& bounds, std::string* out) const;
  };
  static constexpr std::array<double, 14> kRequestBounds = {
      0.0001, 0.00025, 0.0005, 0.001, 0.0025, 0.005, 0.01,
      0.025,  0.05,    0.1,    0.25,  0.5,    1.0,   5.0};
  static constexpr std::array<double, 10> kCalibrationBounds = {
      1, 5, 10, 30, 60, 120, 300, 600, 1800, 3600};

  // Answers of one route and method by exact status code: slot i counts
  // code[i], claimed (0 -> code) by compare-and-swap on first use.
  struct CodeCounts {
    static constexpr size_t kSlots = 24;
    std::array<std::atomic<int>, kSlots> code{};
    std::array<std::atomic<uint64_t>, kSlots> n{};
    std::atomic<uint64_t> other{0};  // slots full, or not 100..599
    void Count(int status);
    void Render(std::string_view labels, std::string* out) const;
  };
  void RenderRequests(std::string* out) const;

  BuildInfo build_;
  std::array<std::array<Histogram<14>, kNumMethods>, kNumRoutes> requests_;
  std::array<std::array<CodeCounts, kNumMethods>, kNumRoutes> codes_;
  std::atomic<int64_t> coils_ingested_{0};
  std::array<std::atomic<uint64_t>, kNumConnectionEvents> connections_{};
  std::atomic<int64_t> calibrations_done_{0};
  std::atomic<int64_t> calibrations_failed_{0};
  Histogram<10> calibration_seconds_;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_METRICS_H_
