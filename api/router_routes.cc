// The route table: every endpoint of docs/api.md declared once. Order
// matters only where two patterns take the same path: a literal
// ("/v1/models/active") comes before the parameter that would also take it
// ("/v1/models/{version}"). Two routes with the same pattern (GET and POST
// /v1/calibrations) are told apart by method; the first of them labels a
// 405. tests/e2e/openapi_test.py reads the method and pattern of each row
// (`{RouteId::k..., "METHOD", "/pattern", ...`) and checks that
// docs/openapi.yaml documents it.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/router.h"

namespace rollwear::api {

using E = Execution;

const std::vector<Router::Route>& Router::Routes() {
  using A = const PathArgs&;
  using Q = const HttpRequest&;
  // One row per endpoint, wider than 80 columns to stay one line.
  // clang-format off
  static const auto* routes = new std::vector<Route>{
      // Ingestion (POST, token).
      {{RouteId::kRollChanges, "POST", "/v1/roll-changes", true, E::kBlocking},
       [](Router& r, Q q, A) { return r.PostRollChange(q); }},
      {{RouteId::kCampaignEnd, "POST", "/v1/campaigns/{campaign_id*}/end", true, E::kBlocking},
       [](Router& r, Q q, A a) { return r.PostCampaignEnd(q, a[0]); }},
      {{RouteId::kCoils, "POST", "/v1/coils", true, E::kAsync},
       [](Router& r, Q q, A) { return r.PostCoil(q); }},
      {{RouteId::kMeasurements, "POST", "/v1/measurements", true, E::kBlocking},
       [](Router& r, Q q, A) { return r.PostMeasurement(q); }},
      {{RouteId::kProfiles, "POST", "/v1/profiles", true, E::kBlocking},
       [](Router& r, Q q, A) { return r.PostProfile(q); }},
      // Wear, limits and the forecast.
      {{RouteId::kWear, "GET", "/v1/wear", false, E::kInline},
       [](Router& r, Q, A) { return r.GetWear(); }},
      {{RouteId::kWearProfile, "GET", "/v1/wear/{stand}/{position}/profile", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetWearProfile(a[0], a[1]); }},
      {{RouteId::kWearAt, "GET", "/v1/wear/{stand}/{position}", false, E::kInline},
       [](Router& r, Q, A a) { return r.GetWearAt(a[0], a[1]); }},
      {{RouteId::kLimits, "GET", "/v1/limits", false, E::kBlocking},
       [](Router& r, Q, A) { return r.GetLimits(); }},
      {{RouteId::kLimitSet, "POST", "/v1/limits/{stand}/{position}", true, E::kBlocking},
       [](Router& r, Q q, A a) { return r.PostLimit(q, a[0], a[1]); }},
      {{RouteId::kForecast, "POST", "/v1/forecast", true, E::kBlocking},
       [](Router& r, Q q, A) { return r.PostForecast(q); }},
      // Calibrations and models.
      {{RouteId::kCalibrationsList, "GET", "/v1/calibrations", false, E::kBlocking},
       [](Router& r, Q q, A) { return r.ListCalibrations(q); }},
      {{RouteId::kCalibrationsPost, "POST", "/v1/calibrations", true, E::kBlocking},
       [](Router& r, Q q, A) { return r.PostCalibration(q); }},
      {{RouteId::kCalibration, "GET", "/v1/calibrations/{id}", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetCalibration(a[0]); }},
      {{RouteId::kModels, "GET", "/v1/models", false, E::kBlocking},
       [](Router& r, Q q, A) { return r.ListModels(q); }},
      {{RouteId::kModelsActive, "GET", "/v1/models/active", false, E::kBlocking},
       [](Router& r, Q, A) { return r.GetActiveModel(); }},
      {{RouteId::kModelHistory, "GET", "/v1/models/history", false, E::kBlocking},
       [](Router& r, Q q, A) { return r.GetModelHistory(q); }},
      {{RouteId::kModel, "GET", "/v1/models/{version}", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetModel(a[0]); }},
      {{RouteId::kModelActivate, "POST", "/v1/models/{version}/activate", true, E::kBlocking},
       [](Router& r, Q q, A a) { return r.PostActivate(q, a[0]); }},
      // Diagnoses.
      {{RouteId::kDiagnosesList, "GET", "/v1/diagnoses", false, E::kBlocking},
       [](Router& r, Q q, A) { return r.ListDiagnoses(q); }},
      {{RouteId::kDiagnosesPost, "POST", "/v1/diagnoses", true, E::kBlocking},
       [](Router& r, Q q, A) { return r.PostDiagnosis(q); }},
      {{RouteId::kDiagnosis, "GET", "/v1/diagnoses/{id}", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetDiagnosis(a[0]); }},
      {{RouteId::kDiagnosisReport, "GET", "/v1/diagnoses/{id}/report", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetDiagnosisReport(a[0]); }},
      // Rolls, pages and operations.
      {{RouteId::kRolls, "GET", "/v1/rolls", false, E::kBlocking},
       [](Router& r, Q, A) { return r.GetRolls(); }},
      {{RouteId::kRoll, "GET", "/v1/rolls/{roll_id*}", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetRoll(a[0]); }},
      {{RouteId::kDashboard, "GET", "/", false, E::kBlocking},
       [](Router& r, Q, A) { return r.GetDashboard(); }},
      {{RouteId::kRollPage, "GET", "/rolls/{roll_id*}", false, E::kBlocking},
       [](Router& r, Q, A a) { return r.GetRollPage(a[0]); }},
      {{RouteId::kHealthz, "GET", "/healthz", false, E::kBlocking},
       [](Router& r, Q, A) { return r.GetHealth(); }},
      {{RouteId::kMetrics, "GET", "/metrics", false, E::kBlocking},
       [](Router& r, Q, A) { return r.GetMetrics(); }},
  };
  // clang-format on
  return *routes;
}

const RouteSpec& RouteSpecOf(RouteId id) {
  // Indexed by RouteId once, from the table (every id but kUnmatched is
  // declared exactly once: RouteTableTest; a second declaration stops the
  // process at its first request).
  static const auto* by_id = [] {
    auto* specs = new std::array<RouteSpec, kNumRoutes>();
    (*specs)[static_cast<int>(RouteId::kUnmatched)] =
        RouteSpec{RouteId::kUnmatched, "", "unmatched", false, E::kInline};
    for (const Router::Route& route : Router::Routes()) {
      RouteSpec& slot = (*specs)[static_cast<int>(route.spec.id)];
      if (*slot.pattern != '\0') {
        std::fprintf(stderr, "route table: route %d declared twice (%s)\n",
                     static_cast<int>(route.spec.id), route.spec.pattern);
        std::abort();
      }
      slot = route.spec;
    }
    return specs;
  }();
  return (*by_id)[static_cast<int>(id)];
}

const char* RouteLabel(RouteId id) {
  // The patterns without the '*' of a rest parameter, once.
  static const auto* labels = [] {
    auto* out = new std::array<std::string, kNumRoutes>();
    for (int i = 0; i < kNumRoutes; ++i) {
      for (const char* c = RouteSpecOf(static_cast<RouteId>(i)).pattern;
           *c != '\0'; ++c) {
        if (*c != '*') (*out)[i] += *c;
      }
    }
    return out;
  }();
  return (*labels)[static_cast<int>(id)].c_str();
}

Router::RouteMatch Router::Match(const std::string& path,
                                 const std::string& method) {
  const bool get = method == "GET" || method == "HEAD";
  const bool post = method == "POST";
  RouteMatch match;
  const char* matched_pattern = nullptr;
  for (const Route& route : Routes()) {
    if (matched_pattern != nullptr) {
      // Only a route declared with the same pattern may still take it.
      if (std::string_view(route.spec.pattern) != matched_pattern) continue;
    } else {
      PathArgs args;
      if (!MatchPattern(route.spec.pattern, path, &args)) continue;
      matched_pattern = route.spec.pattern;
      match.route = &route;  // labels a 405 when no method fits
      match.args = std::move(args);
    }
    const bool wants_post = std::string_view(route.spec.method) == "POST";
    if ((wants_post && post) || (!wants_post && get)) {
      match.route = &route;
      match.method_allowed = true;
      return match;
    }
  }
  return match;
}

std::string Router::AllowedMethods(const char* pattern) {
  bool get = false, post = false;
  for (const Route& route : Routes()) {
    if (std::string_view(route.spec.pattern) != pattern) continue;
    (std::string_view(route.spec.method) == "POST" ? post : get) = true;
  }
  return std::string(get ? "GET, HEAD" : "") + (get && post ? ", " : "") +
         (post ? "POST" : "");
}

}  // namespace rollwear::api
