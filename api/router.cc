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

// The 500 answer for the exception being handled (call inside a catch).
HttpResponse InternalErrorAnswer() {
  try {
    throw;
  } catch (const std::exception& e) {
    return Error(500, "internal", std::string("internal error: ") + e.what());
  } catch (...) {
    return Error(500, "internal", "internal error");
  }
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
  if (*stand != 0 && ParsePosition(position_text, position))
    return std::nullopt;
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
    : store_(store),
      mounted_(store),
      options_(std::move(options)),
      metrics_(options_.build) {}

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

Router::Routed Router::RouteRequest(const HttpRequest& request) const {
  Routed routed;
  RouteMatch match = Match(request.path, request.method);
  if (match.route == nullptr) {
    routed.refused =
        Error(404, "not_found", "no such endpoint: " + request.path);
    return routed;
  }
  const RouteSpec& spec = match.route->spec;
  routed.route = match.route;
  routed.args = std::move(match.args);
  if (!match.method_allowed) {
    HttpResponse r = Error(405, "method_not_allowed",
                           "method " + request.method + " is not allowed on " +
                               RouteLabel(spec.id));
    r.headers.emplace_back("Allow", AllowedMethods(spec.pattern));
    r.route = spec.id;
    routed.refused = std::move(r);
    return routed;
  }
  routed.refused = RefuseBeforeHandler(request, spec);
  routed.execution = routed.refused ? Execution::kInline : spec.execution;
  return routed;
}

std::optional<HttpResponse> Router::PreCheck(const HttpRequest& head) const {
  Routed routed = RouteRequest(head);
  // Labelled with the request's own method, as Handle() labels: a PUT
  // refused from its head alone is counted as PUT, not as the route's POST.
  if (routed.refused) {
    routed.refused->route.method = ParseHttpMethod(head.method);
  }
  return std::move(routed.refused);
}

HttpResponse Router::Handle(const HttpRequest& request) {
  Routed routed;
  try {
    routed = RouteRequest(request);
  } catch (...) {
    routed.refused = InternalErrorAnswer();
  }
  return Handle(request, routed);
}

HttpResponse Router::Handle(const HttpRequest& request, const Routed& routed) {
  HttpResponse response;
  try {
    if (routed.refused) {
      response = *routed.refused;
    } else {
      response = routed.route->handler(*this, request, routed.args);
      response.route = routed.route->spec.id;
    }
  } catch (...) {
    response = InternalErrorAnswer();
  }
  response.route.method = ParseHttpMethod(request.method);
  return response;
}

std::optional<HttpResponse> Router::RefuseBeforeHandler(
    const HttpRequest& request, const RouteSpec& spec) const {
  std::optional<HttpResponse> response;
  if (spec.needs_token && !Authorized(request)) {
    response = Error(401, "unauthorized",
                     "this endpoint needs the header 'Authorization: "
                     "Bearer <token>' with the configured token");
  } else if (std::string_view(spec.method) == "POST" &&
             request.body.size() > options_.body_limit_bytes) {
    response = Error(413, "payload_too_large",
                     "the body has " + std::to_string(request.body.size()) +
                         " bytes; the limit is " +
                         std::to_string(options_.body_limit_bytes));
  }
  if (response) response->route = spec.id;
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

void Router::HandleAsync(const HttpRequest& request, const Routed& routed,
                         Done done,
                         const storage::MillStore::Executor& blocking) {
  if (routed.refused || routed.route == nullptr ||
      routed.route->spec.id != RouteId::kCoils) {
    done(Handle(request, routed));
    return;
  }
  // Only an accepted POST /v1/coils gets here; DecodeCoilBody labels
  // kCoils, whose own method is POST.
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
        } catch (...) {
          response = InternalErrorAnswer();
        }
        response.route = RouteId::kCoils;
        done(std::move(response));
      },
      blocking);
}

HttpResponse Router::PostMeasurement(const HttpRequest& request) {
  return router_internal::PostRecord(
      request, options_.max_json_depth, &DecodeMeasurement,
      [this](storage::MeasurementIn* in) {
        return store_->AddMeasurement(*in, &in->suspect);  // flags `in`
      },
      &EncodeMeasurementAnswer);
}

HttpResponse Router::GetMetrics() {
  StoreFigures figures;
  figures.healthy = store_->Healthy();
  figures.counters = store_->Counters();
  figures.validation_gap_um = std::numeric_limits<double>::quiet_NaN();
  figures.wear = mounted_.Wear().positions;
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
