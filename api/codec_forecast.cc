// The bodies of the remaining-life endpoints: POST /v1/forecast (decoded
// coil by coil with DecodeCoil, so a planned coil obeys exactly the rules
// of POST /v1/coils) and the wear limits (GET /v1/limits, POST
// /v1/limits/{stand}/{position}'s answer).
//
// Thread-safety: stateless functions (as codec.h).
#include <optional>
#include <string>
#include <utility>

#include "api/codec.h"
#include "api/json_scan.h"
#include "api/json_writer.h"
#include "core/dataset/timestamp.h"

namespace rollwear::api {
namespace {

// The error of coils[i] as decoded on its own, named by its path in the
// forecast body.
ApiError InCoil(size_t i, ApiError e) {
  const std::string prefix = "coils[" + std::to_string(i) + "]";
  if (!e.field.empty() && e.message.compare(0, e.field.size(), e.field) == 0) {
    e.message = prefix + "." + e.message;
  } else {
    e.message = prefix + ": " + e.message;
  }
  e.field = e.field.empty() ? prefix : prefix + "." + e.field;
  return e;
}

void WriteLimitMembers(JsonWriter* w, const storage::WearLimit& l) {
  w->Key("stand");
  w->String(StandName(l.stand));
  w->Key("position");
  w->String(PositionName(l.position));
  w->Key("limit_um");
  w->OptionalDouble(l.limit_um);
  w->Key("source");
  if (l.source.empty()) {
    w->Null();
  } else {
    w->String(l.source);
  }
  w->Key("set_at");
  if (l.source == "api") {
    w->String(FormatTimestamp(l.set_at));
  } else {
    w->Null();
  }
  w->Key("reason");
  if (l.source == "api" && !l.reason.empty()) {
    w->String(l.reason);
  } else {
    w->Null();
  }
}

void WriteForecastPosition(JsonWriter* w, const engine::ForecastPosition& p,
                           const std::vector<std::string>& coil_ids) {
  w->BeginObject();
  w->Key("stand");
  w->String(StandName(p.stand));
  w->Key("position");
  w->String(PositionName(p.position));
  w->Key("roll_id");
  w->String(p.roll_id);
  w->Key("campaign_id");
  w->String(p.campaign_id);
  w->Key("wear_limit_um");
  w->OptionalDouble(p.wear_limit_um);
  w->Key("predicted_wear_um");
  w->BeginArray();
  for (double d : p.predicted_wear_um) w->Double(d);
  w->EndArray();
  w->Key("interval_um");
  w->BeginArray();
  for (const auto& [lo, hi] : p.interval_um) {
    w->BeginArray();
    w->Double(lo);
    w->Double(hi);
    w->EndArray();
  }
  w->EndArray();
  w->Key("first_crossing");
  if (p.first_crossing < 0) {
    w->Null();
  } else {
    w->BeginObject();
    w->Key("index");
    w->Int(p.first_crossing);
    w->Key("coil_id");
    w->String(coil_ids[static_cast<size_t>(p.first_crossing)]);
    w->EndObject();
  }
  w->EndObject();
}

}  // namespace

bool DecodeForecast(std::string_view body, int max_depth, size_t max_coils,
                    std::vector<storage::CoilIn>* out, ApiError* error) {
  std::vector<std::string> elements;
  if (!SplitListBody(body, max_depth, "coils", max_coils, &elements, error)) {
    return false;
  }
  if (elements.empty()) {
    *error = ApiError{400, "out_of_range", "coils must hold at least one coil",
                      "coils"};
    return false;
  }
  out->clear();
  out->resize(elements.size());
  for (size_t i = 0; i < elements.size(); ++i) {
    // An element sits one level below the body.
    if (!DecodeCoil(elements[i], max_depth - 1, &(*out)[i], error)) {
      *error = InCoil(i, std::move(*error));
      return false;
    }
  }
  return true;
}

std::string EncodeWearLimits(const std::vector<storage::WearLimit>& limits) {
  JsonWriter w(64 + 160 * limits.size());
  w.BeginObject();
  w.Key("limits");
  w.BeginArray();
  for (const storage::WearLimit& l : limits) {
    w.BeginObject();
    WriteLimitMembers(&w, l);
    w.EndObject();
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

std::string EncodeWearLimit(const storage::WearLimit& limit) {
  JsonWriter w(200 + limit.reason.size());
  w.BeginObject();
  WriteLimitMembers(&w, limit);
  w.EndObject();
  return w.Take();
}

std::string EncodeForecast(const engine::Forecast& forecast) {
  size_t reserve = 64;
  for (const auto& p : forecast.positions) {
    reserve += 160 + 64 * p.predicted_wear_um.size();
  }
  JsonWriter w(reserve);
  w.BeginObject();
  w.Key("model_version");
  w.Int(forecast.model_version);
  w.Key("coils");
  w.Int(static_cast<int64_t>(forecast.coil_ids.size()));
  w.Key("positions");
  w.BeginArray();
  for (const auto& p : forecast.positions) {
    WriteForecastPosition(&w, p, forecast.coil_ids);
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

}  // namespace rollwear::api
