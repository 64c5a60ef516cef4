// Router: the whole HTTP API of docs/api.md as a function from request to
// response, with no sockets (after Valhalla's actor/service split). It
// matches the route, checks the bearer token and the body limit, decodes and
// validates the JSON body into storage's input types, calls the MillStore
// facade, and encodes the answer or the error body
//   {"error": {"code": "...", "message": "...", "field": "passes[1].force_kn"}}
// HTTP status codes exist in the api layer only; HttpStatusFor() is the one
// mapping from core's StatusCode. A rejected request never reaches a write
// of the store, so it changes nothing. router.cc holds the matching, the
// token check, the dispatch, the asynchronous coil path, measurements and
// metrics; router_handlers.cc the other endpoints; router_forecast.cc the
// wear limits and the forecast; dashboard.cc the page.
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
#include "core/base/status.h"
#include "core/model/wear_law.h"
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

// Percent-decodes `in` (and '+' to a space when `plus_is_space`, for query
// strings). Returns false on a malformed escape. (Defined with the request
// parser, api/http_parser.cc; the router decodes path parameters with it.)
bool PercentDecode(std::string_view in, bool plus_is_space, std::string* out);

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
  // Runs POST /v1/diagnoses (the daemon's service::DiagnosisJobs); not
  // owned, must outlive the router. Null: no diagnoses here (POST answers
  // 503 "unavailable", GET 404).
  DiagnosisRunner* diagnoses = nullptr;
  // Version and commit of the build, for rollwear_build_info.
  BuildInfo build;

  bool IsValid(std::string* error) const;
};

// The HTTP status for a store or core error: InvalidArgument 400, NotFound
// 404, AlreadyExists 409, FailedPrecondition 422, Unavailable 503, anything
// else 500.
int HttpStatusFor(StatusCode code);

// Where a server should run a request (Router::Plan).
enum class Execution {
  // Handle() answers from memory without waiting on the disk or a lock held
  // across SQL (wear reads, 404/405 answers): run it on the I/O thread.
  kInline,
  // POST /v1/coils: HandleAsync() queues it for the group commit and
  // answers from the store's writer thread.
  kAsync,
  // Anything else may wait on SQLite or a calibration: run Handle() on a
  // worker thread.
  kBlocking,
};

class Router {
 public:
  // `store` must outlive the router.
  Router(storage::MillStore* store, ApiOptions options);

  Router(const Router&) = delete;
  Router& operator=(const Router&) = delete;

  HttpResponse Handle(const HttpRequest& request);

  // The refusal Handle() would give from the request's head alone - 404
  // (no route), 405 (method), 401 (token), 413 (body over the limit, for
  // what is already in) - or nullopt. Cheap and without side effects: the
  // server asks it as soon as a head is in, before "100 Continue" and
  // before reading the body.
  std::optional<HttpResponse> PreCheck(const HttpRequest& head) const;

  // Cheap and without side effects: how Handle()/HandleAsync() will run
  // this request.
  Execution Plan(const HttpRequest& request) const;
  // The answer of Handle(), given to `done` exactly once: for a coil that
  // is queued, on the store's writer thread after its group commit; for
  // the repeat of a stored coil, through `blocking` (it reads the first
  // answer from the database); otherwise on the calling thread before
  // HandleAsync returns (so only kAsync and kInline requests belong here).
  // `done` must be quick.
  using Done = std::function<void(HttpResponse)>;
  void HandleAsync(const HttpRequest& request, Done done,
                   const storage::MillStore::Executor& blocking);

  // Request and calibration figures exposed by GET /metrics; the HTTP server
  // records request latencies here, the scheduler calibration runs.
  Metrics* metrics() { return &metrics_; }
  const ApiOptions& options() const { return options_; }

 private:
  HttpResponse Dispatch(const HttpRequest& request);
  HttpResponse PostRollChange(const HttpRequest& request);
  HttpResponse PostCampaignEnd(const HttpRequest& request,
                               const std::string& campaign_id);
  HttpResponse PostCoil(const HttpRequest& request);
  // Decodes a coil body into `in`; the error answer when it is refused.
  std::optional<HttpResponse> DecodeCoilBody(const HttpRequest& request,
                                             storage::CoilIn* in) const;
  HttpResponse CoilAnswer(const storage::CoilIn& in,
                          const StatusOr<storage::CoilOutcome>& outcome);
  // PreCheck, also giving the route and its path parameters.
  std::optional<HttpResponse> PreCheck(const HttpRequest& head, RouteId* route,
                                       std::string* arg1,
                                       std::string* arg2) const;
  // The refusal Dispatch gives before a POST's handler runs (401, 413), or
  // an empty optional.
  std::optional<HttpResponse> RefusePost(const HttpRequest& request,
                                         RouteId route) const;
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
  // router_shop.cc: models under control, rolls, stored diagnoses,
  // profiles (router_profile.cc).
  HttpResponse DispatchShop(RouteId route, const HttpRequest& request,
                            const std::string& arg);
  HttpResponse GetModel(const std::string& version);
  HttpResponse PostActivate(const HttpRequest& request,
                            const std::string& version);
  HttpResponse GetModelHistory(const HttpRequest& request);
  HttpResponse GetRoll(const std::string& roll_id);
  HttpResponse GetRolls();
  HttpResponse ListDiagnoses(const HttpRequest& request);
  HttpResponse GetDiagnosisReport(const std::string& id);
  // The stored diagnosis `id` as a job (with its adoption's run), or none.
  std::optional<DiagnosisJob> StoredDiagnosisJob(int64_t id) const;
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
  ApiOptions options_;
  Metrics metrics_;
  // Id of the last diagnosis queued (0: none), for the dashboard.
  std::atomic<int64_t> last_diagnosis_id_{0};
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_ROUTER_H_
