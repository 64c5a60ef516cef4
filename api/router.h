// Router: the whole HTTP API of docs/api.md as a function from request to
// response, with no sockets (after Valhalla's actor/service split). It
// matches the route, checks the bearer token and the body limit, decodes and
// validates the JSON body into storage's input types, calls the MillStore
// facade (writes and records) or the engine (the mounted rolls' wear,
// engine/mounted_rolls.h), and encodes the answer or the error body
//   {"error": {"code": "...", "message": "...", "field": "passes[1].force_kn"}}
// HTTP status codes exist in the api layer only; HttpStatusFor() is the one
// mapping from core's StatusCode. A rejected request never reaches a write
// of the store, so it changes nothing. router_routes.cc holds the route
// table (each endpoint declared once: api/routes.h) and the matching;
// router.cc the checks, the dispatch, the asynchronous coil path,
// measurements and metrics; router_handlers.cc, router_shop.cc and
// router_profile.cc the other endpoints; router_forecast.cc the wear limits
// and the forecast; dashboard.cc the page.
//
// Thread-safety: Handle() is thread-safe (the store is; the router's own
// state is immutable options and the lock-free Metrics).
#ifndef ROLLWEAR_API_ROUTER_H_
#define ROLLWEAR_API_ROUTER_H_

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/diagnosis_job.h"
#include "api/metrics.h"
#include "api/routes.h"
#include "core/base/status.h"
#include "core/model/wear_law.h"
#include "engine/mounted_rolls.h"
#include "storage/mill_store.h"

namespace rollwear::api {

struct HttpRequest {
  std::string method;  // "GET", "POST", ...
  std::string path;    // path without the query string, decoded but for
                       // %2F and %25 (api/http_parser.h)
  // Header names as sent; lookups are case-insensitive.
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;
  std::map<std::string, std::string> params;  // decoded query parameters
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // extra headers
  // The labels of the request metrics: the route template that answered
  // ("/v1/coils", "/v1/wear/{stand}/{position}", "unmatched") and the
  // request's method (set by Handle/HandleAsync).
  RequestLabels route;
};

struct ApiOptions {
  // Bearer token every POST must carry; empty = no authentication.
  std::string token;
  // Largest accepted request body; larger ones are answered 413.
  size_t body_limit_bytes = 1 << 20;
  // Deepest accepted nesting of JSON arrays/objects (a coil needs 3).
  int max_json_depth = 16;
  // Most coils one POST /v1/forecast may plan (more: 413).
  size_t max_forecast_coils = 10000;
  // Law and K option of POST /v1/calibrations without a body.
  WearLaw default_law = WearLaw::kWang;
  int default_option = 1;
  // Called with the id of every calibration queued through the API, so the
  // job worker runs it; may be empty (the run then stays queued).
  std::function<void(int64_t)> on_calibration_queued;
  // Runs POST /v1/diagnoses (the daemon's engine::DiagnosisJobs); not
  // owned, must outlive the router. Null: no diagnoses here (POST answers
  // 503 "unavailable", GET 404).
  engine::DiagnosisRunner* diagnoses = nullptr;
  // Version and commit of the build, for rollwear_build_info.
  BuildInfo build;

  bool IsValid(std::string* error) const;
};

// The HTTP status for a store or core error: InvalidArgument 400, NotFound
// 404, AlreadyExists 409, FailedPrecondition 422, Unavailable 503, anything
// else 500.
int HttpStatusFor(StatusCode code);

class Router {
  struct Route;

 public:
  // `store` must outlive the router.
  Router(storage::MillStore* store, ApiOptions options);

  Router(const Router&) = delete;
  Router& operator=(const Router&) = delete;

  // A request routed once (RouteRequest): the route that took it (null:
  // none took the path) and its path parameters, the refusal its head alone
  // gets (404 no route, 405 method, 401 token, 413 body over the limit, for
  // what is already in), and how the server should run it. Handle and
  // HandleAsync take it, so a request is matched once.
  struct Routed {
    const Route* route = nullptr;
    PathArgs args;
    std::optional<HttpResponse> refused;
    Execution execution = Execution::kInline;
  };
  // Cheap and without side effects: the server asks it as soon as a
  // request is in (and PreCheck as soon as its head is).
  Routed RouteRequest(const HttpRequest& request) const;

  // The answer to a routed request (the refusal, or the handler's answer).
  HttpResponse Handle(const HttpRequest& request, const Routed& routed);
  // RouteRequest then Handle (tests, and callers without a server).
  HttpResponse Handle(const HttpRequest& request);

  // The refusal Handle() would give from the request's head alone, or
  // nullopt: before "100 Continue" and before reading the body.
  std::optional<HttpResponse> PreCheck(const HttpRequest& head) const;

  // The answer of Handle(), given to `done` exactly once: for a coil that
  // is queued, on the store's writer thread after its group commit; for
  // the repeat of a stored coil, through `blocking` (it reads the first
  // answer from the database); otherwise on the calling thread before
  // HandleAsync returns (so only kAsync and kInline requests belong here).
  // `done` must be quick.
  using Done = std::function<void(HttpResponse)>;
  void HandleAsync(const HttpRequest& request, const Routed& routed, Done done,
                   const storage::MillStore::Executor& blocking);

  // Request and calibration figures exposed by GET /metrics; the HTTP server
  // records request latencies here, the scheduler calibration runs.
  Metrics* metrics() { return &metrics_; }
  const ApiOptions& options() const { return options_; }

 private:
  friend const RouteSpec& RouteSpecOf(RouteId id);
  // One row of the route table: the spec and the handler that answers
  // what passed the checks.
  struct Route {
    RouteSpec spec;
    HttpResponse (*handler)(Router& router, const HttpRequest& request,
                            const PathArgs& args);
  };
  // The route table (api/router_routes.cc).
  static const std::vector<Route>& Routes();
  // The first route whose pattern takes `path` (null: none) and its
  // parameters; `method_allowed` when it, or a route declared with the
  // same pattern, answers `method` (then that route).
  struct RouteMatch {
    const Route* route = nullptr;
    bool method_allowed = false;
    PathArgs args;
  };
  static RouteMatch Match(const std::string& path, const std::string& method);
  // "GET, HEAD", "POST" or "GET, HEAD, POST": what the routes declared with
  // `pattern` answer (a 405's Allow header).
  static std::string AllowedMethods(const char* pattern);
  // The refusal before a handler runs (401 token, 413 body), or nullopt.
  std::optional<HttpResponse> RefuseBeforeHandler(const HttpRequest& request,
                                                  const RouteSpec& spec) const;

  HttpResponse PostRollChange(const HttpRequest& request);
  HttpResponse PostCampaignEnd(const HttpRequest& request,
                               const std::string& campaign_id);
  HttpResponse PostCoil(const HttpRequest& request);
  // Decodes a coil body into `in`; the error answer when it is refused.
  std::optional<HttpResponse> DecodeCoilBody(const HttpRequest& request,
                                             storage::CoilIn* in) const;
  HttpResponse CoilAnswer(const storage::CoilIn& in,
                          const StatusOr<storage::CoilOutcome>& outcome);
  HttpResponse GetWear();
  HttpResponse GetWearAt(const std::string& stand, const std::string& position);
  HttpResponse PostMeasurement(const HttpRequest& request);
  HttpResponse PostCalibration(const HttpRequest& request);
  HttpResponse GetCalibration(const std::string& id);
  HttpResponse ListCalibrations(const HttpRequest& request);
  HttpResponse GetActiveModel();
  HttpResponse ListModels(const HttpRequest& request);
  HttpResponse GetHealth();
  HttpResponse GetMetrics();
  HttpResponse PostDiagnosis(const HttpRequest& request);
  HttpResponse GetDiagnosis(const std::string& id);
  // Wear limits and the forecast (api/router_forecast.cc).
  HttpResponse GetLimits();
  HttpResponse PostLimit(const HttpRequest& request, const std::string& stand,
                         const std::string& position);
  HttpResponse PostForecast(const HttpRequest& request);
  // router_shop.cc: models under control, rolls, stored diagnoses.
  HttpResponse GetModel(const std::string& version);
  HttpResponse PostActivate(const HttpRequest& request,
                            const std::string& version);
  HttpResponse GetModelHistory(const HttpRequest& request);
  HttpResponse GetRoll(const std::string& roll_id);
  HttpResponse GetRolls();
  HttpResponse ListDiagnoses(const HttpRequest& request);
  HttpResponse GetDiagnosisReport(const std::string& id);
  // The stored diagnosis `id` as a job (with its adoption's run), or none.
  std::optional<engine::DiagnosisJob> StoredDiagnosisJob(int64_t id) const;
  // router_profile.cc: grinder profiles and the predicted profile.
  HttpResponse PostProfile(const HttpRequest& request);
  HttpResponse GetWearProfile(const std::string& stand,
                              const std::string& position);
  // dashboard_roll.cc: the roll page (HTML).
  HttpResponse GetRollPage(const std::string& roll_id);
  // GET /: the HTML dashboard (api/dashboard.cc).
  HttpResponse GetDashboard();

  // True when no token is configured or the request carries it as
  // "Authorization: Bearer <token>" (compared in constant time).
  bool Authorized(const HttpRequest& request) const;

  storage::MillStore* store_;
  // The engine's answers about the mounted rolls (wear, profile, forecast).
  engine::MountedRolls mounted_;
  ApiOptions options_;
  Metrics metrics_;
  // Id of the last diagnosis queued (0: none), for the dashboard.
  std::atomic<int64_t> last_diagnosis_id_{0};
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_ROUTER_H_
