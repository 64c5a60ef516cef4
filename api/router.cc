#include "api/router.h"

#include <charconv>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>

#include <strings.h>

#include "api/codec.h"
#include "api/router_internal.h"

namespace rollwear::api {

using router_internal::Answer;
using router_internal::Error;
using router_internal::FromStatus;
using router_internal::ParseInt64;

namespace {

constexpr std::string_view kCampaignsPrefix = "/v1/campaigns/";
constexpr std::string_view kEndSuffix = "/end";
constexpr std::string_view kWearPrefix = "/v1/wear/";
constexpr std::string_view kLimitsPrefix = "/v1/limits/";
constexpr std::string_view kCalibrationsPrefix = "/v1/calibrations/";
constexpr std::string_view kDiagnosesPrefix = "/v1/diagnoses/";
constexpr std::string_view kModelsPrefix = "/v1/models/";
constexpr std::string_view kRollsPrefix = "/v1/rolls/";
constexpr std::string_view kRollPagePrefix = "/rolls/";
constexpr std::string_view kActivateSuffix = "/activate";
constexpr std::string_view kReportSuffix = "/report";

// A path parameter: the parser leaves "%2F" and "%25" encoded in the path
// (api/http_parser.h) so that they do not split segments; decode them here.
std::string Segment(std::string_view raw) {
  std::string out;
  if (!PercentDecode(raw, false, &out)) return std::string(raw);
  return out;
}

// `p` is prefix + one non-empty segment without '/' (+ suffix): the
// segment, decoded, or nullopt.
std::optional<std::string> ParamBetween(std::string_view p,
                                        std::string_view prefix,
                                        std::string_view suffix = "") {
  if (p.size() <= prefix.size() + suffix.size() ||
      p.substr(0, prefix.size()) != prefix ||
      p.substr(p.size() - suffix.size()) != suffix) {
    return std::nullopt;
  }
  const std::string_view mid =
      p.substr(prefix.size(), p.size() - prefix.size() - suffix.size());
  if (mid.find('/') != std::string_view::npos) return std::nullopt;
  return Segment(mid);
}

bool IsPathChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
         (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '[' || c == ']';
}

// The JSON path a store message starts with ("passes[1].force_kn: must be
// > 0" -> "passes[1].force_kn"), or "".
std::string FieldOf(const std::string& message) {
  const size_t colon = message.find(": ");
  if (colon == std::string::npos || colon == 0 || colon > 80) return "";
  const char first = message[0];
  if (!((first >= 'a' && first <= 'z') || (first >= 'A' && first <= 'Z'))) {
    return "";
  }
  for (size_t i = 0; i < colon; ++i) {
    if (!IsPathChar(message[i])) return "";
  }
  return message.substr(0, colon);
}

const std::string* FindHeader(const HttpRequest& request,
                              std::string_view name) {
  for (const auto& [key, value] : request.headers) {
    if (key.size() == name.size() &&
        strncasecmp(key.data(), name.data(), name.size()) == 0) {
      return &value;
    }
  }
  return nullptr;
}

// Compares in time that depends on the lengths only, not on where the
// strings first differ.
bool ConstantTimeEquals(std::string_view a, std::string_view b) {
  const size_t n = a.size() > b.size() ? a.size() : b.size();
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? a[i] : 0;
    const unsigned char y = i < b.size() ? b[i] : 0;
    diff |= x ^ y;
  }
  return diff == 0;
}

HttpResponse MethodNotAllowed(RouteId route, const std::string& method) {
  HttpResponse r =
      Error(405, "method_not_allowed",
            "method " + method + " is not allowed on " + RoutePath(route));
  const bool both = route == RouteId::kCalibrationsPost ||
                    route == RouteId::kCalibrationsList ||
                    route == RouteId::kDiagnosesPost ||
                    route == RouteId::kDiagnosesList;
  const bool post = std::string_view(RouteMethod(route)) == "POST";
  r.headers.emplace_back("Allow", both   ? "GET, HEAD, POST"
                                  : post ? "POST"
                                         : "GET, HEAD");
  r.route = route;
  return r;
}


// "{a}/{b}" after `prefix` into *arg1, *arg2 (both non-empty, no more
// slashes); false when `path` is not of that form.
bool MatchTwoParams(std::string_view path, std::string_view prefix,
                    std::string* arg1, std::string* arg2) {
  if (path.substr(0, prefix.size()) != prefix) return false;
  const std::string_view rest = path.substr(prefix.size());
  const size_t slash = rest.find('/');
  if (slash == std::string_view::npos || slash == 0 ||
      slash + 1 >= rest.size() ||
      rest.find('/', slash + 1) != std::string_view::npos) {
    return false;
  }
  *arg1 = Segment(rest.substr(0, slash));
  *arg2 = Segment(rest.substr(slash + 1));
  return true;
}

// The route of `path` (kUnmatched when none) and its path parameters.
RouteId MatchRoute(const std::string& path, bool post, std::string* arg1,
                   std::string* arg2) {
  if (path == "/v1/roll-changes") return RouteId::kRollChanges;
  if (path == "/v1/coils") return RouteId::kCoils;
  if (path == "/v1/wear") return RouteId::kWear;
  if (path == "/v1/measurements") return RouteId::kMeasurements;
  if (path == "/v1/calibrations") {
    return post ? RouteId::kCalibrationsPost : RouteId::kCalibrationsList;
  }
  if (path == "/v1/models/active") return RouteId::kModelsActive;
  if (path == "/v1/models") return RouteId::kModels;
  if (path == "/healthz") return RouteId::kHealthz;
  if (path == "/metrics") return RouteId::kMetrics;
  if (path == "/v1/diagnoses") {
    return post ? RouteId::kDiagnosesPost : RouteId::kDiagnosesList;
  }
  if (path == "/v1/models/history") return RouteId::kModelHistory;
  if (path == "/v1/rolls") return RouteId::kRolls;
  if (path == "/") return RouteId::kDashboard;
  if (path == "/v1/limits") return RouteId::kLimits;
  if (path == "/v1/forecast") return RouteId::kForecast;
  if (path == "/v1/profiles") return RouteId::kProfiles;
  const std::string_view p(path);
  if (std::optional<std::string> a = ParamBetween(p, kModelsPrefix)) {
    *arg1 = std::move(*a);
    return RouteId::kModel;
  }
  if (std::optional<std::string> a =
          ParamBetween(p, kModelsPrefix, kActivateSuffix)) {
    *arg1 = std::move(*a);
    return RouteId::kModelActivate;
  }
  if (std::optional<std::string> a =
          ParamBetween(p, kDiagnosesPrefix, kReportSuffix)) {
    *arg1 = std::move(*a);
    return RouteId::kDiagnosisReport;
  }
  // A roll id may hold any character, '/' included (sent as %2F).
  if (p.size() > kRollsPrefix.size() &&
      p.substr(0, kRollsPrefix.size()) == kRollsPrefix) {
    *arg1 = Segment(p.substr(kRollsPrefix.size()));
    return RouteId::kRoll;
  }
  if (p.size() > kRollPagePrefix.size() &&
      p.substr(0, kRollPagePrefix.size()) == kRollPagePrefix) {
    *arg1 = Segment(p.substr(kRollPagePrefix.size()));
    return RouteId::kRollPage;
  }
  if (p.size() > kCampaignsPrefix.size() + kEndSuffix.size() &&
      p.substr(0, kCampaignsPrefix.size()) == kCampaignsPrefix &&
      p.substr(p.size() - kEndSuffix.size()) == kEndSuffix) {
    // The id may hold any character, '/' included (sent as %2F).
    *arg1 = Segment(
        p.substr(kCampaignsPrefix.size(),
                 p.size() - kCampaignsPrefix.size() - kEndSuffix.size()));
    return RouteId::kCampaignEnd;
  }
  if (p.substr(0, kWearPrefix.size()) == kWearPrefix) {
    constexpr std::string_view kProfileSuffix = "/profile";
    if (p.size() > kWearPrefix.size() + kProfileSuffix.size() &&
        p.substr(p.size() - kProfileSuffix.size()) == kProfileSuffix) {
      return MatchTwoParams(p.substr(0, p.size() - kProfileSuffix.size()),
                            kWearPrefix, arg1, arg2)
                 ? RouteId::kWearProfile
                 : RouteId::kUnmatched;
    }
    return MatchTwoParams(p, kWearPrefix, arg1, arg2) ? RouteId::kWearAt
                                                      : RouteId::kUnmatched;
  }
  if (p.substr(0, kLimitsPrefix.size()) == kLimitsPrefix) {
    return MatchTwoParams(p, kLimitsPrefix, arg1, arg2) ? RouteId::kLimitSet
                                                        : RouteId::kUnmatched;
  }
  if (p.substr(0, kCalibrationsPrefix.size()) == kCalibrationsPrefix &&
      p.size() > kCalibrationsPrefix.size() &&
      p.find('/', kCalibrationsPrefix.size()) == std::string_view::npos) {
    *arg1 = Segment(p.substr(kCalibrationsPrefix.size()));
    return RouteId::kCalibration;
  }
  if (p.substr(0, kDiagnosesPrefix.size()) == kDiagnosesPrefix &&
      p.size() > kDiagnosesPrefix.size() &&
      p.find('/', kDiagnosesPrefix.size()) == std::string_view::npos) {
    *arg1 = Segment(p.substr(kDiagnosesPrefix.size()));
    return RouteId::kDiagnosis;
  }
  return RouteId::kUnmatched;
}

const char* ErrorCodeFor(StatusCode code) {
  switch (code) {
    case StatusCode::kInvalidArgument:
      return "invalid_value";
    case StatusCode::kNotFound:
      return "not_found";
    case StatusCode::kAlreadyExists:
      return "conflict";
    case StatusCode::kFailedPrecondition:
      return "inconsistent";
    case StatusCode::kUnavailable:
      return "unavailable";
    default:
      return "internal";
  }
}

}  // namespace

namespace router_internal {

HttpResponse Answer(int status, std::string body) {
  HttpResponse r;
  r.status = status;
  r.body = std::move(body);
  return r;
}

HttpResponse Error(const ApiError& e) {
  HttpResponse r = Answer(e.status, EncodeError(e));
  if (e.status == 503) r.headers.emplace_back("Retry-After", "1");
  if (e.status == 401) r.headers.emplace_back("WWW-Authenticate", "Bearer");
  return r;
}

HttpResponse Error(int status, std::string code, std::string message,
                   std::string field) {
  return Error(
      ApiError{status, std::move(code), std::move(message), std::move(field)});
}

// The one translation of a store/core error into an HTTP error answer. A
// bad field (400) and an inconsistent one (422) name it.
HttpResponse FromStatus(const Status& status) {
  const int http = HttpStatusFor(status.code());
  std::string field =
      http == 400 || http == 422 ? FieldOf(status.message()) : "";
  return Error(http, ErrorCodeFor(status.code()), status.message(),
               std::move(field));
}

std::optional<HttpResponse> ParseRollPosition(const std::string& stand_text,
                                              const std::string& position_text,
                                              int* stand, Position* position) {
  *stand = ParseStand(stand_text);
  if (*stand != 0 && ParsePosition(position_text, position)) return std::nullopt;
  return Error(404, "not_found",
               "unknown roll position '" + stand_text + "/" + position_text +
                   "' (stands F1..F7, positions top or bottom)");
}

bool ParseInt64(std::string_view text, int64_t* out) {
  if (text.empty()) return false;
  const auto [p, ec] =
      std::from_chars(text.data(), text.data() + text.size(), *out);
  return ec == std::errc() && p == text.data() + text.size();
}

std::optional<HttpResponse> ReadLimit(const HttpRequest& request,
                                      int64_t* limit) {
  *limit = 50;
  auto it = request.params.find("limit");
  if (it != request.params.end() &&
      (!ParseInt64(it->second, limit) || *limit < 1 || *limit > 1000)) {
    return Error(400, "out_of_range", "limit must be an integer in [1, 1000]",
                 "limit");
  }
  return std::nullopt;
}

}  // namespace router_internal

bool ApiOptions::IsValid(std::string* error) const {
  if (body_limit_bytes < 256) {
    *error = "body_limit_bytes must be >= 256";
    return false;
  }
  if (max_json_depth < 4 || max_json_depth > 256) {
    *error = "max_json_depth must be in [4, 256]";
    return false;
  }
  if (default_option < 1 || default_option > 3) {
    *error = "default option must be 1, 2 or 3";
    return false;
  }
  return true;
}

int HttpStatusFor(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return 200;
    case StatusCode::kInvalidArgument:
      return 400;
    case StatusCode::kNotFound:
      return 404;
    case StatusCode::kAlreadyExists:
      return 409;
    case StatusCode::kFailedPrecondition:
      return 422;
    case StatusCode::kUnavailable:
      return 503;
    case StatusCode::kNumericalFailure:
    case StatusCode::kIoError:
    case StatusCode::kInternal:
      return 500;
  }
  return 500;
}

Router::Router(storage::MillStore* store, ApiOptions options)
    : store_(store), options_(std::move(options)), metrics_(options_.build) {}

HttpResponse Router::Handle(const HttpRequest& request) {
  HttpResponse response;
  try {
    response = Dispatch(request);
  } catch (const std::exception& e) {
    response =
        Error(500, "internal", std::string("internal error: ") + e.what());
  } catch (...) {
    response = Error(500, "internal", "internal error");
  }
  response.route.method = ParseHttpMethod(request.method);
  return response;
}

bool Router::Authorized(const HttpRequest& request) const {
  if (options_.token.empty()) return true;
  const std::string* value = FindHeader(request, "Authorization");
  if (value == nullptr || value->size() < 7 ||
      strncasecmp(value->data(), "Bearer ", 7) != 0) {
    return false;
  }
  std::string_view presented(*value);
  presented.remove_prefix(7);
  while (!presented.empty() && presented.front() == ' ') {
    presented.remove_prefix(1);
  }
  while (!presented.empty() &&
         (presented.back() == ' ' || presented.back() == '\t')) {
    presented.remove_suffix(1);
  }
  return ConstantTimeEquals(presented, options_.token);
}

std::optional<HttpResponse> Router::PreCheck(const HttpRequest& head,
                                             RouteId* route, std::string* arg1,
                                             std::string* arg2) const {
  const bool get = head.method == "GET" || head.method == "HEAD";
  const bool post = head.method == "POST";
  *route = MatchRoute(head.path, post, arg1, arg2);
  if (*route == RouteId::kUnmatched) {
    return Error(404, "not_found", "no such endpoint: " + head.path);
  }
  const bool wants_post = std::string_view(RouteMethod(*route)) == "POST";
  if ((wants_post && !post) || (!wants_post && !get)) {
    return MethodNotAllowed(*route, head.method);
  }
  if (post) return RefusePost(head, *route);
  return std::nullopt;
}

std::optional<HttpResponse> Router::PreCheck(const HttpRequest& head) const {
  RouteId route;
  std::string arg1, arg2;
  std::optional<HttpResponse> refused = PreCheck(head, &route, &arg1, &arg2);
  // Labelled with the request's own method, as Handle() labels: a PUT
  // refused from its head alone is counted as PUT, not as the route's POST.
  if (refused) refused->route.method = ParseHttpMethod(head.method);
  return refused;
}

HttpResponse Router::Dispatch(const HttpRequest& request) {
  const std::string& path = request.path;
  std::string arg1, arg2;
  RouteId route;
  if (std::optional<HttpResponse> refused =
          PreCheck(request, &route, &arg1, &arg2)) {
    return std::move(*refused);
  }
  HttpResponse response;
  switch (route) {
    case RouteId::kRollChanges:
      response = PostRollChange(request);
      break;
    case RouteId::kCampaignEnd:
      response = PostCampaignEnd(request, arg1);
      break;
    case RouteId::kCoils:
      response = PostCoil(request);
      break;
    case RouteId::kWear:
      response = GetWear();
      break;
    case RouteId::kWearAt:
      response = GetWearAt(arg1, arg2);
      break;
    case RouteId::kWearProfile:
      response = GetWearProfile(arg1, arg2);
      break;
    case RouteId::kMeasurements:
      response = PostMeasurement(request);
      break;
    case RouteId::kCalibrationsPost:
      response = PostCalibration(request);
      break;
    case RouteId::kCalibrationsList:
      response = ListCalibrations(request);
      break;
    case RouteId::kCalibration:
      response = GetCalibration(arg1);
      break;
    case RouteId::kModelsActive:
      response = GetActiveModel();
      break;
    case RouteId::kModels:
      response = ListModels(request);
      break;
    case RouteId::kHealthz:
      response = GetHealth();
      break;
    case RouteId::kMetrics:
      response = GetMetrics();
      break;
    case RouteId::kDiagnosesPost:
      response = PostDiagnosis(request);
      break;
    case RouteId::kDiagnosis:
      response = GetDiagnosis(arg1);
      break;
    case RouteId::kDashboard:
      response = GetDashboard();
      break;
    case RouteId::kLimits:
      response = GetLimits();
      break;
    case RouteId::kLimitSet:
      response = PostLimit(request, arg1, arg2);
      break;
    case RouteId::kForecast:
      response = PostForecast(request);
      break;
    case RouteId::kModel:
    case RouteId::kModelActivate:
    case RouteId::kModelHistory:
    case RouteId::kRolls:
    case RouteId::kRoll:
    case RouteId::kDiagnosesList:
    case RouteId::kDiagnosisReport:
    case RouteId::kRollPage:
    case RouteId::kProfiles:
      response = DispatchShop(route, request, arg1);  // router_shop.cc
      break;
    default:
      response = Error(404, "not_found", "no such endpoint: " + path);
      break;
  }
  response.route = route;
  return response;
}

std::optional<HttpResponse> Router::RefusePost(const HttpRequest& request,
                                               RouteId route) const {
  std::optional<HttpResponse> response;
  if (!Authorized(request)) {
    response = Error(401, "unauthorized",
                     "this endpoint needs the header 'Authorization: "
                     "Bearer <token>' with the configured token");
  } else if (request.body.size() > options_.body_limit_bytes) {
    response = Error(413, "payload_too_large",
                     "the body has " + std::to_string(request.body.size()) +
                         " bytes; the limit is " +
                         std::to_string(options_.body_limit_bytes));
  }
  if (response) response->route = route;
  return response;
}

std::optional<HttpResponse> Router::DecodeCoilBody(const HttpRequest& request,
                                                   storage::CoilIn* in) const {
  ApiError error;
  if (DecodeCoil(request.body, options_.max_json_depth, in, &error)) {
    return std::nullopt;
  }
  HttpResponse response = Error(error);
  response.route = RouteId::kCoils;
  return response;
}

HttpResponse Router::PostCoil(const HttpRequest& request) {
  storage::CoilIn in;
  if (std::optional<HttpResponse> refused = DecodeCoilBody(request, &in)) {
    return std::move(*refused);
  }
  return CoilAnswer(in, store_->AddCoil(in));
}

HttpResponse Router::CoilAnswer(const storage::CoilIn& in,
                                const StatusOr<storage::CoilOutcome>& outcome) {
  if (!outcome.ok()) return FromStatus(outcome.status());
  const bool created = outcome->outcome == storage::WriteOutcome::kCreated;
  if (created) metrics_.CountCoilIngested();
  return Answer(created ? 201 : 200, EncodeCoilAnswer(in, *outcome, -1));
}

Execution Router::Plan(const HttpRequest& request) const {
  const bool post = request.method == "POST";
  std::string arg1, arg2;
  switch (MatchRoute(request.path, post, &arg1, &arg2)) {
    case RouteId::kCoils:
      return post ? Execution::kAsync : Execution::kInline;
    case RouteId::kWear:
    case RouteId::kWearAt:
    case RouteId::kUnmatched:
      return Execution::kInline;
    default:
      return Execution::kBlocking;
  }
}

void Router::HandleAsync(const HttpRequest& request, Done done,
                         const storage::MillStore::Executor& blocking) {
  std::string arg1, arg2;
  if (request.method != "POST" || MatchRoute(request.path, /*post=*/true, &arg1,
                                             &arg2) != RouteId::kCoils) {
    done(Handle(request));
    return;
  }
  // Only a POST gets here, and RefusePost/DecodeCoilBody label kCoils,
  // whose own method is POST.
  std::optional<HttpResponse> refused = RefusePost(request, RouteId::kCoils);
  if (refused) {
    done(std::move(*refused));
    return;
  }
  auto in = std::make_shared<storage::CoilIn>();
  if (std::optional<HttpResponse> refused = DecodeCoilBody(request, in.get())) {
    done(std::move(*refused));
    return;
  }
  store_->AddCoilAsync(
      *in,
      [this, in,
       done = std::move(done)](StatusOr<storage::CoilOutcome> outcome) {
        HttpResponse response;
        try {
          response = CoilAnswer(*in, outcome);
        } catch (const std::exception& e) {
          response = Error(500, "internal",
                           std::string("internal error: ") + e.what());
        } catch (...) {
          response = Error(500, "internal", "internal error");
        }
        response.route = RouteId::kCoils;
        done(std::move(response));
      },
      blocking);
}

HttpResponse Router::PostMeasurement(const HttpRequest& request) {
  storage::MeasurementIn in;
  ApiError error;
  if (!DecodeMeasurement(request.body, options_.max_json_depth, &in, &error)) {
    return Error(error);
  }
  auto outcome = store_->AddMeasurement(in, &in.suspect);  // flags `in`
  if (!outcome.ok()) return FromStatus(outcome.status());
  return Answer(*outcome == storage::WriteOutcome::kCreated ? 201 : 200,
                EncodeMeasurementAnswer(in, *outcome));
}

HttpResponse Router::GetMetrics() {
  StoreFigures figures;
  figures.healthy = store_->Healthy();
  figures.counters = store_->Counters();
  figures.validation_gap_um = std::numeric_limits<double>::quiet_NaN();
  figures.wear = store_->Wear().positions;
  StatusOr<storage::ModelVersion> model = store_->ActiveModel();
  if (model.ok()) {
    figures.model_version = model->version;
    if (model->version > 0) figures.validation_gap_um = model->gap_val_um;
  }
  HttpResponse r = Answer(200, metrics_.Render(figures));
  r.content_type = "text/plain; version=0.0.4; charset=utf-8";
  return r;
}

}  // namespace rollwear::api
