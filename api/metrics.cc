#include "api/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "api/process_metrics.h"

namespace rollwear::api {
namespace {

// Prometheus float: shortest round-trip form, "+Inf"/"NaN" spelled out.
std::string Float(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  // The shortest of %.6g, %.15g, %.17g that reads back as v.
  char buf[32];
  for (const char* format : {"%.6g", "%.15g"}) {
    std::snprintf(buf, sizeof(buf), format, v);
    if (std::strtod(buf, nullptr) == v) return buf;
  }
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

void Header(std::string* out, const char* name, const char* type,
            const char* help) {
  *out += "# HELP ";
  *out += name;
  *out += ' ';
  *out += help;
  *out += "\n# TYPE ";
  *out += name;
  *out += ' ';
  *out += type;
  *out += '\n';
}

void Sample(std::string* out, std::string_view name, std::string_view labels,
            const std::string& value) {
  out->append(name);
  if (!labels.empty()) {
    *out += '{';
    out->append(labels);
    *out += '}';
  }
  *out += ' ';
  *out += value;
  *out += '\n';
}

constexpr const char* kMethods[kNumMethods] = {
    "GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS", "OTHER"};

std::string RouteLabels(int r, int m) {
  return std::string("route=\"") + RoutePath(static_cast<RouteId>(r)) +
         "\",method=\"" +
         kMethods[m] + "\"";
}

// A label value with \, " and newline escaped (exposition format 0.0.4).
std::string Escaped(std::string_view value) {
  std::string out;
  for (char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    out += c == '\n' ? std::string("\\n") : std::string(1, c);
  }
  return out;
}

}  // namespace

const char* RoutePath(RouteId route) { return RouteLabel(route); }
const char* RouteMethod(RouteId route) { return RouteSpecOf(route).method; }

HttpMethod ParseHttpMethod(std::string_view method) {
  for (int m = 0; m < kNumMethods - 1; ++m) {
    if (method == kMethods[m]) return static_cast<HttpMethod>(m);
  }
  return HttpMethod::kOther;
}

const char* HttpMethodName(HttpMethod method) {
  return kMethods[static_cast<int>(method)];
}

RequestLabels::RequestLabels(RouteId route)
    : route_id(route), method(ParseHttpMethod(RouteMethod(route))) {}

void Metrics::CodeCounts::Count(int status) {
  if (status < 100 || status > 599) {
    other.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  for (size_t i = 0; i < kSlots; ++i) {
    int held = code[i].load(std::memory_order_acquire);
    if (held == 0) {
      // Claim the free slot; when another thread claimed it first,
      // `expected` is its code.
      int expected = 0;
      held = code[i].compare_exchange_strong(expected, status,
                                             std::memory_order_acq_rel)
                 ? status
                 : expected;
    }
    if (held == status) {
      n[i].fetch_add(1, std::memory_order_relaxed);
      return;
    }
  }
  other.fetch_add(1, std::memory_order_relaxed);
}

void Metrics::CodeCounts::Render(std::string_view labels,
                                 std::string* out) const {
  std::vector<std::pair<int, uint64_t>> rows;
  for (size_t i = 0; i < kSlots; ++i) {
    const int c = code[i].load(std::memory_order_acquire);
    const uint64_t count = n[i].load(std::memory_order_relaxed);
    if (c != 0 && count != 0) rows.emplace_back(c, count);
  }
  std::sort(rows.begin(), rows.end());
  const std::string prefix = std::string(labels) + ",code=\"";
  for (const auto& [c, count] : rows) {
    Sample(out, "rollwear_http_requests_total",
           prefix + std::to_string(c) + "\"", std::to_string(count));
  }
  const uint64_t rest = other.load(std::memory_order_relaxed);
  if (rest != 0) {
    Sample(out, "rollwear_http_requests_total", prefix + "other\"",
           std::to_string(rest));
  }
}

template <size_t N>
void Metrics::Histogram<N>::Observe(const std::array<double, N>& bounds,
                                    double seconds) {
  for (size_t i = 0; i < N; ++i) {
    if (seconds <= bounds[i]) {
      buckets[i].fetch_add(1, std::memory_order_relaxed);
      break;
    }
  }
  count.fetch_add(1, std::memory_order_relaxed);
  const double ns = seconds > 0 ? seconds * 1e9 : 0;
  sum_ns.fetch_add(static_cast<uint64_t>(ns), std::memory_order_relaxed);
}

template <size_t N>
void Metrics::Histogram<N>::Render(std::string_view name,
                                   std::string_view labels,
                                   const std::array<double, N>& bounds,
                                   std::string* out) const {
  const std::string prefix =
      labels.empty() ? std::string() : std::string(labels) + ",";
  const std::string bucket = std::string(name) + "_bucket";
  uint64_t cumulative = 0;
  for (size_t i = 0; i < N; ++i) {
    cumulative += buckets[i].load(std::memory_order_relaxed);
    Sample(out, bucket, prefix + "le=\"" + Float(bounds[i]) + "\"",
           std::to_string(cumulative));
  }
  // Read count after the buckets so that +Inf >= every finite bucket.
  uint64_t total = count.load(std::memory_order_relaxed);
  if (total < cumulative) total = cumulative;
  Sample(out, bucket, prefix + "le=\"+Inf\"", std::to_string(total));
  Sample(
      out, std::string(name) + "_sum", labels,
      Float(static_cast<double>(sum_ns.load(std::memory_order_relaxed)) / 1e9));
  Sample(out, std::string(name) + "_count", labels, std::to_string(total));
}

void Metrics::ObserveRequest(RequestLabels labels, int status,
                             double seconds) {
  const int r = static_cast<int>(labels.route_id);
  const int m = static_cast<int>(labels.method);
  requests_[r][m].Observe(kRequestBounds, seconds);
  codes_[r][m].Count(status);
}

void Metrics::RenderRequests(std::string* out) const {
  Header(out, "rollwear_http_request_duration_seconds", "histogram",
         "Time from request read to answer ready, by route and method.");
  for (int r = 0; r < kNumRoutes; ++r) {
    for (int m = 0; m < kNumMethods; ++m) {
      if (requests_[r][m].count.load(std::memory_order_relaxed) == 0) continue;
      requests_[r][m].Render("rollwear_http_request_duration_seconds",
                             RouteLabels(r, m), kRequestBounds, out);
    }
  }
  Header(out, "rollwear_http_requests_total", "counter",
         "Answered requests by route, method and exact status code.");
  for (int r = 0; r < kNumRoutes; ++r) {
    for (int m = 0; m < kNumMethods; ++m) {
      codes_[r][m].Render(RouteLabels(r, m), out);
    }
  }
}

void Metrics::ObserveCalibration(bool succeeded, double seconds) {
  (succeeded ? calibrations_done_ : calibrations_failed_)
      .fetch_add(1, std::memory_order_relaxed);
  calibration_seconds_.Observe(kCalibrationBounds, seconds);
}

const char* ConnectionEventName(ConnectionEvent event) {
  switch (event) {
    case ConnectionEvent::kRefusedGlobalCap:
      return "refused_global_cap";
    case ConnectionEvent::kRefusedPerClient:
      return "refused_per_client_limit";
    case ConnectionEvent::kTimeoutHead:
      return "timeout_head_deadline";
    case ConnectionEvent::kTimeoutBody:
      return "timeout_body_deadline";
    case ConnectionEvent::kTimeoutIdle:
      return "timeout_idle";
    case ConnectionEvent::kTimeoutWrite:
      return "timeout_write";
    case ConnectionEvent::kInputBudget:
      return "throttled_input_budget";
    case ConnectionEvent::kCount:
      break;
  }
  return "unknown";
}

std::string Metrics::Render(const StoreFigures& store) const {
  std::string out;
  out.reserve(16384);

  Header(&out, "rollwear_up", "gauge",
         "1 when the database answers a trivial query.");
  Sample(&out, "rollwear_up", "", store.healthy ? "1" : "0");

  Header(&out, "rollwear_coils_ingested_total", "counter",
         "Coils newly stored through POST /v1/coils since start (repeats "
         "not counted).");
  Sample(&out, "rollwear_coils_ingested_total", "",
         std::to_string(coils_ingested()));

  Header(&out, "rollwear_group_commits_total", "counter",
         "Group-commit transactions of the store's writer.");
  Sample(&out, "rollwear_group_commits_total", "",
         std::to_string(store.counters.commits));

  Header(&out, "rollwear_build_info", "gauge",
         "Always 1; the labels name the build's version and git commit.");
  Sample(&out, "rollwear_build_info",
         "version=\"" + Escaped(build_.version) + "\",commit=\"" +
             Escaped(build_.commit) + "\"",
         "1");

  RenderRequests(&out);

  Header(&out, "rollwear_http_connections_total", "counter",
         "Connections refused, timed out or throttled by the HTTP server, "
         "by event.");
  for (int e = 0; e < kNumConnectionEvents; ++e) {
    Sample(&out, "rollwear_http_connections_total",
           std::string("event=\"") +
               ConnectionEventName(static_cast<ConnectionEvent>(e)) + "\"",
           std::to_string(connections_[e].load(std::memory_order_relaxed)));
  }

  Header(&out, "rollwear_calibration_runs_total", "counter",
         "Finished calibration runs since start, by outcome.");
  Sample(&out, "rollwear_calibration_runs_total", "status=\"done\"",
         std::to_string(calibrations_done_.load(std::memory_order_relaxed)));
  Sample(&out, "rollwear_calibration_runs_total", "status=\"failed\"",
         std::to_string(calibrations_failed_.load(std::memory_order_relaxed)));

  Header(&out, "rollwear_calibration_duration_seconds", "histogram",
         "Wall time of calibration runs.");
  calibration_seconds_.Render("rollwear_calibration_duration_seconds", "",
                              kCalibrationBounds, &out);

  Header(&out, "rollwear_validation_gap_um", "gauge",
         "Validation wear gap (mean |measured - predicted|, um) of the "
         "active model; NaN for the prior model.");
  Sample(&out, "rollwear_validation_gap_um", "",
         Float(store.validation_gap_um));

  Header(&out, "rollwear_model_version", "gauge",
         "Version of the active wear model (0 = prior).");
  Sample(&out, "rollwear_model_version", "",
         std::to_string(store.model_version));

  Header(&out, "rollwear_coils_stored", "gauge", "Coils in the database.");
  Sample(&out, "rollwear_coils_stored", "",
         std::to_string(store.counters.coils));
  Header(&out, "rollwear_campaigns_stored", "gauge",
         "Campaigns in the database.");
  Sample(&out, "rollwear_campaigns_stored", "",
         std::to_string(store.counters.campaigns));
  Header(&out, "rollwear_measurements_stored", "gauge",
         "Grinder measurements in the database.");
  Sample(&out, "rollwear_measurements_stored", "",
         std::to_string(store.counters.measurements));
  Header(&out, "rollwear_measurements_since_last_calibration", "gauge",
         "Measurements stored since the last calibration run.");
  Sample(&out, "rollwear_measurements_since_last_calibration", "",
         std::to_string(store.counters.measurements_since_last_calibration));
  Header(&out, "rollwear_measurements_suspect_stored", "gauge",
         "Measurements stored flagged as suspect (kept, not fitted).");
  Sample(&out, "rollwear_measurements_suspect_stored", "",
         std::to_string(store.counters.suspect_measurements));

  Header(&out, "rollwear_predicted_wear_um", "gauge",
         "Predicted centre wear of the roll mounted at each stand and "
         "position (GET /v1/wear), um.");
  for (const engine::PositionWear& w : store.wear) {
    Sample(&out, "rollwear_predicted_wear_um",
           "stand=\"F" + std::to_string(w.stand) + "\",position=\"" +
               PositionName(w.position) + "\"",
           Float(w.predicted_wear_um));
  }
  AppendProcessMetrics(&out);
  return out;
}

}  // namespace rollwear::api
