// The HTTP API's route table: each endpoint is declared once, in
// api/router_routes.cc (method, path pattern, whether it needs the token,
// how the server runs it, its handler, and its metrics label RouteId), and
// a request is matched against it once (Router::Route). This header holds
// the table's plain data and the pattern matcher; the handlers are the
// Router's (api/router.h).
//
// Patterns: literal text with parameters in braces. "{name}" takes one
// non-empty path segment (no '/'); "{name*}" takes a non-empty rest that
// may hold '/' (a roll or campaign id sent with %2F, or raw), followed only
// by literal text. Parameters are percent-decoded (the request parser
// leaves %2F and %25 encoded so that they do not split segments,
// api/http_parser.h).
//
// Thread-safety: the table is immutable after its first use (a function
// static); MatchPattern and RouteSpecOf are pure and thread-safe.
#ifndef ROLLWEAR_API_ROUTES_H_
#define ROLLWEAR_API_ROUTES_H_

#include <array>
#include <string>
#include <string_view>

namespace rollwear::api {

// Each route, and the `route` label of the request metrics (api/metrics.h):
// its method and path pattern are declared once, in the table.
enum class RouteId : int {
  kRollChanges = 0,
  kCampaignEnd,
  kCoils,
  kWear,
  kWearAt,
  kMeasurements,
  kCalibrationsPost,
  kCalibrationsList,
  kCalibration,
  kModelsActive,
  kModels,
  kHealthz,
  kMetrics,
  kDiagnosesPost,
  kDiagnosis,
  kDashboard,
  kLimits,
  kLimitSet,
  kForecast,
  kModel,
  kModelActivate,
  kModelHistory,
  kRolls,
  kRoll,
  kDiagnosesList,
  kDiagnosisReport,
  kRollPage,
  kProfiles,
  kWearProfile,
  kUnmatched,  // anything else (404/405)
  kCount
};
constexpr int kNumRoutes = static_cast<int>(RouteId::kCount);

// Percent-decodes `in` (and '+' to a space when `plus_is_space`, for query
// strings). Returns false on a malformed escape. (Defined with the request
// parser, api/http_parser.cc; the router decodes path parameters with it.)
bool PercentDecode(std::string_view in, bool plus_is_space, std::string* out);

// Where a server should run a request (Router::RouteRequest).
enum class Execution {
  // Answered from memory without waiting on the disk or a lock held across
  // SQL (wear reads, every refusal from the head): the I/O thread.
  kInline,
  // POST /v1/coils: Router::HandleAsync queues it for the group commit and
  // answers from the store's writer thread.
  kAsync,
  // May wait on SQLite or a calibration: a worker thread.
  kBlocking,
};

// One endpoint, as declared in the table.
struct RouteSpec {
  RouteId id = RouteId::kUnmatched;
  const char* method = "";   // "GET" (HEAD is answered too) or "POST"
  const char* pattern = "";  // "/v1/wear/{stand}/{position}"
  bool needs_token = false;  // the bearer token, when one is configured
  Execution execution = Execution::kBlocking;
};

// The path parameters of a matched route, in pattern order.
using PathArgs = std::array<std::string, 2>;

// Whether `path` has the form of `pattern`; fills `args` (decoded) when it
// has. A pattern holds at most two parameters.
bool MatchPattern(std::string_view pattern, std::string_view path,
                  PathArgs* args);

// The declared spec of `id` (for kUnmatched: method "", pattern
// "unmatched").
const RouteSpec& RouteSpecOf(RouteId id);
// The `route` label of the request metrics and the path named in messages:
// the pattern with a rest parameter written as the OpenAPI path template
// ("/v1/rolls/{roll_id}"); "unmatched" for kUnmatched.
const char* RouteLabel(RouteId id);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_ROUTES_H_
