#include "api/metrics.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace rollwear::api {
namespace {

struct RouteInfo {
  const char* path;
  const char* method;
};

constexpr RouteInfo kRoutes[kNumRoutes] = {
    {"/v1/roll-changes", "POST"},
    {"/v1/campaigns/{campaign_id}/end", "POST"},
    {"/v1/coils", "POST"},
    {"/v1/wear", "GET"},
    {"/v1/wear/{stand}/{position}", "GET"},
    {"/v1/measurements", "POST"},
    {"/v1/calibrations", "POST"},
    {"/v1/calibrations", "GET"},
    {"/v1/calibrations/{id}", "GET"},
    {"/v1/models/active", "GET"},
    {"/v1/models", "GET"},
    {"/healthz", "GET"},
    {"/metrics", "GET"},
    {"/v1/diagnoses", "POST"},
    {"/v1/diagnoses/{id}", "GET"},
    {"/", "GET"},
    {"/v1/limits", "GET"},
    {"/v1/limits/{stand}/{position}", "POST"},
    {"/v1/forecast", "POST"},
    {"unmatched", ""},
};

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

std::string RouteLabels(int r) {
  return std::string("route=\"") + kRoutes[r].path + "\",method=\"" +
         kRoutes[r].method + "\"";
}

}  // namespace

const char* RoutePath(RouteId route) {
  return kRoutes[static_cast<int>(route)].path;
}
const char* RouteMethod(RouteId route) {
  return kRoutes[static_cast<int>(route)].method;
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

void Metrics::ObserveRequest(RouteId route, int status, double seconds) {
  const int r = static_cast<int>(route);
  requests_[r].Observe(kRequestBounds, seconds);
  const int cls = status >= 500 ? 2 : status >= 400 ? 1 : 0;
  codes_[r][cls].fetch_add(1, std::memory_order_relaxed);
}

void Metrics::ObserveCalibration(bool succeeded, double seconds) {
  (succeeded ? calibrations_done_ : calibrations_failed_)
      .fetch_add(1, std::memory_order_relaxed);
  calibration_seconds_.Observe(kCalibrationBounds, seconds);
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

  Header(&out, "rollwear_http_request_duration_seconds", "histogram",
         "Time from request read to answer ready, by route.");
  for (int r = 0; r < kNumRoutes; ++r) {
    if (requests_[r].count.load(std::memory_order_relaxed) == 0) continue;
    requests_[r].Render("rollwear_http_request_duration_seconds",
                        RouteLabels(r), kRequestBounds, &out);
  }

  Header(&out, "rollwear_http_requests_total", "counter",
         "Answered requests by route and status class.");
  static constexpr const char* kClasses[3] = {"2xx", "4xx", "5xx"};
  for (int r = 0; r < kNumRoutes; ++r) {
    for (int c = 0; c < 3; ++c) {
      const uint64_t n = codes_[r][c].load(std::memory_order_relaxed);
      if (n == 0) continue;
      Sample(&out, "rollwear_http_requests_total",
             RouteLabels(r) + ",code=\"" + kClasses[c] + "\"",
             std::to_string(n));
    }
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
  return out;
}

}  // namespace rollwear::api
