// The answer bodies of docs/api.md (see codec.h). Those of the hot
// endpoints (errors, coils, wear) go through JsonWriter, which prints what
// the DOM's dump() would; the rest build an nlohmann DOM.
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "api/codec.h"
#include "api/codec_json_util.h"
#include "api/json_writer.h"
#include "core/dataset/dataset_io.h"
#include "core/model/ann_model.h"
#include "storage/model_codec.h"

namespace rollwear::api {
namespace {

using codec_internal::Dump;
using codec_internal::FiniteOrNull;
using codec_internal::Json;
using codec_internal::OutcomeName;
using codec_internal::TimeOrNull;

const char* StatusName(storage::CalibrationStatus s) {
  switch (s) {
    case storage::CalibrationStatus::kQueued:
      return "queued";
    case storage::CalibrationStatus::kRunning:
      return "running";
    case storage::CalibrationStatus::kDone:
      return "done";
    case storage::CalibrationStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

// Stand numbers as "F6"; any int prints as the DOM encoders printed it.
void WriteStand(JsonWriter* w, int stand) {
  char text[16] = {'F'};
  const auto result = std::to_chars(text + 1, text + sizeof(text), stand);
  w->String(std::string_view(text, static_cast<size_t>(result.ptr - text)));
}

// [lo, hi] with hi null when unbounded.
void WriteBounds(JsonWriter* w, double lo, const std::optional<double>& hi) {
  w->BeginArray();
  w->Double(lo);
  w->OptionalDouble(hi);
  w->EndArray();
}

// The wear limit and remaining-life members of a mounted roll (null when
// there is no limit or the roll has not worn yet).
void WriteRemainingLife(JsonWriter* w, const engine::PositionWear& p) {
  const std::optional<RemainingLife>& life = p.remaining;
  w->Key("wear_limit_um");
  w->OptionalDouble(p.wear_limit_um);
  if (!life) {
    for (JsonKey key : {JsonKey("remaining_length_m"),
                        JsonKey("remaining_coils"),
                        JsonKey("remaining_length_interval_m"),
                        JsonKey("remaining_coils_interval")}) {
      w->Key(key);
      w->Null();
    }
    return;
  }
  w->Key("remaining_length_m");
  w->Double(life->length_m);
  w->Key("remaining_coils");
  w->Double(life->coils);
  w->Key("remaining_length_interval_m");
  WriteBounds(w, life->length_lo_m, life->length_hi_m);
  w->Key("remaining_coils_interval");
  WriteBounds(w, life->coils_lo, life->coils_hi);
}

// The members of one element of GET /v1/wear, inside an open object.
void WritePositionMembers(JsonWriter* w, const engine::PositionWear& p) {
  w->Key("stand");
  WriteStand(w, p.stand);
  w->Key("position");
  w->String(PositionName(p.position));
  w->Key("roll_id");
  w->String(p.roll_id);
  w->Key("roll_type");
  w->String(p.roll_type);
  w->Key("campaign_id");
  w->String(p.campaign_id);
  w->Key("coils");
  w->Int(p.coils);
  w->Key("rolled_length_m");
  w->Double(p.rolled_length_m);
  w->Key("predicted_wear_um");
  w->Double(p.predicted_wear_um);
  w->Key("interval_um");
  w->BeginArray();
  w->Double(p.interval_lo_um);
  w->Double(p.interval_hi_um);
  w->EndArray();
  WriteRemainingLife(w, p);
}

// Room for one position (its strings come on top).
constexpr size_t kPositionBytes = 420;

Json CalibrationJson(const storage::CalibrationRecord& r) {
  Json coefficients = Json::object();
  for (const auto& [name, value] : r.coefficients) {
    coefficients[name] = FiniteOrNull(value);
  }
  const bool finished = r.status == storage::CalibrationStatus::kDone;
  return Json{
      {"id", r.id},
      {"status", StatusName(r.status)},
      {"trigger", r.trigger},
      {"model", r.model},
      {"option", r.option},
      {"queued_at", TimeOrNull(r.queued_at)},
      {"started_at", TimeOrNull(r.started_at)},
      {"finished_at", TimeOrNull(r.finished_at)},
      {"coefficients", coefficients},
      {"cost", finished ? FiniteOrNull(r.cost) : Json(nullptr)},
      {"gap_train_um", finished ? FiniteOrNull(r.gap_train_um) : Json(nullptr)},
      {"gap_val_um", finished ? FiniteOrNull(r.gap_val_um) : Json(nullptr)},
      {"active_gap_val_um",
       finished ? FiniteOrNull(r.active_gap_val_um) : Json(nullptr)},
      {"n_train", r.n_train},
      {"n_val", r.n_val},
      {"promoted", r.promoted},
      {"model_version",
       r.model_version == 0 ? Json(nullptr) : Json(r.model_version)},
      {"message", r.message}};
}

Json TermsJson(const WearModel& m) {
  return Json::parse(storage::EncodeTerms(m.terms));
}

Json ModelJson(const storage::ModelVersion& m) {
  Json coefficients = Json::object();
  for (const auto& [name, value] : m.wear_model.NamedCoefficients()) {
    coefficients[name] = FiniteOrNull(value);
  }
  Json out{
      {"version", m.version},
      {"model", m.model},
      {"option", m.option},
      {"active", m.active},
      {"coefficients", coefficients},
      // Terms adopted from a diagnosis, as the model store encodes them.
      {"terms", TermsJson(m.wear_model)},
      {"gap_val_um",
       m.version == 0 ? Json(nullptr) : FiniteOrNull(m.gap_val_um)},
      {"noise",
       {{"sd_um", m.wear_model.noise_sd_um}, {"rel", m.wear_model.noise_rel}}},
      {"created_at", TimeOrNull(m.created_at)},
      {"pinned", m.pinned},
      // The run that made it (null: none recorded, e.g. version 0).
      {"run", m.calibration_id == 0
                  ? Json(nullptr)
                  : Json{{"calibration_id", m.calibration_id},
                         {"source", m.source},
                         {"trigger", m.trigger},
                         {"gap_train_um", FiniteOrNull(m.gap_train_um)},
                         {"gap_val_um", FiniteOrNull(m.gap_val_um)},
                         {"n_train", m.n_train},
                         {"n_val", m.n_val}}}};
  if (m.wear_model.is_ann()) {
    const AnnModel& a = *m.wear_model.ann;
    out["ann"] = {{"members", a.members.size()},
                  {"hidden", {a.hidden1, a.hidden2}},
                  {"inputs", a.num_inputs()}};
  }
  return out;
}

}  // namespace

std::string EncodeError(const ApiError& error) {
  JsonWriter w(64 + error.code.size() + error.message.size() +
               error.field.size());
  w.BeginObject();
  w.Key("error");
  w.BeginObject();
  w.Key("code");
  w.String(error.code);
  w.Key("message");
  w.String(error.message);
  w.Key("field");
  if (error.field.empty()) {
    w.Null();
  } else {
    w.String(error.field);
  }
  w.EndObject();
  w.EndObject();
  return w.Take();
}

std::string EncodeRollChangeAnswer(const storage::RollChangeIn& in,
                                   storage::WriteOutcome outcome) {
  return Dump(Json{{"campaign_id", in.campaign_id},
                   {"started_at", FormatTimestamp(in.started_at)},
                   {"rolls", in.rolls.size()},
                   {"outcome", OutcomeName(outcome)}});
}

std::string EncodeCampaignEndAnswer(const std::string& campaign_id,
                                    UnixSeconds ended_at,
                                    storage::WriteOutcome outcome) {
  return Dump(Json{{"campaign_id", campaign_id},
                   {"ended_at", FormatTimestamp(ended_at)},
                   {"outcome", OutcomeName(outcome)}});
}

std::string EncodeCoilAnswer(const storage::CoilIn& in,
                             const storage::CoilOutcome& outcome,
                             int64_t model_version) {
  size_t reserve = 128 + in.coil_id.size() + in.campaign_id.size();
  for (const auto& a : outcome.added) reserve += 112 + a.roll_id.size();
  JsonWriter w(reserve);
  w.BeginObject();
  w.Key("coil_id");
  w.String(in.coil_id);
  w.Key("campaign_id");
  w.String(in.campaign_id);
  w.Key("outcome");
  w.String(OutcomeName(outcome.outcome));
  w.Key("added");
  w.BeginArray();
  for (const auto& a : outcome.added) {
    w.BeginObject();
    w.Key("stand");
    WriteStand(&w, a.stand);
    w.Key("position");
    w.String(PositionName(a.position));
    w.Key("roll_id");
    w.String(a.roll_id);
    w.Key("wear_um");
    w.Double(a.wear_um);
    w.Key("predicted_wear_um");
    w.Double(a.predicted_wear_um);
    w.EndObject();
  }
  w.EndArray();
  if (model_version >= 0) {
    w.Key("model_version");
    w.Int(model_version);
  }
  w.EndObject();
  return w.Take();
}

std::string EncodeMeasurementAnswer(const storage::MeasurementIn& in,
                                    storage::WriteOutcome outcome) {
  return Dump(
      Json{{"campaign_id", in.campaign_id},
           {"stand", StandName(in.stand)},
           {"position", PositionName(in.position)},
           {"outcome", OutcomeName(outcome)},
           {"suspect", in.suspect.empty() ? Json(nullptr) : Json(in.suspect)}});
}

std::string EncodeWear(const engine::WearSnapshot& snapshot) {
  size_t reserve = 64;
  for (const auto& p : snapshot.positions) {
    reserve += kPositionBytes + p.roll_id.size() + p.roll_type.size() +
               p.campaign_id.size();
  }
  JsonWriter w(reserve);
  w.BeginObject();
  w.Key("model_version");
  w.Int(snapshot.model_version);
  w.Key("positions");
  w.BeginArray();
  for (const auto& p : snapshot.positions) {
    w.BeginObject();
    WritePositionMembers(&w, p);
    w.EndObject();
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

std::string EncodePositionWear(const engine::PositionWear& wear,
                               int64_t model_version) {
  JsonWriter w(kPositionBytes + 32 + wear.roll_id.size() +
               wear.roll_type.size() + wear.campaign_id.size());
  w.BeginObject();
  WritePositionMembers(&w, wear);
  w.Key("model_version");
  w.Int(model_version);
  w.EndObject();
  return w.Take();
}

std::string EncodeCalibrationId(int64_t id) {
  return Dump(Json{{"id", id}, {"status", "queued"}});
}

std::string EncodeCalibration(const storage::CalibrationRecord& record) {
  return Dump(CalibrationJson(record));
}

std::string EncodeCalibrationList(
    const std::vector<storage::CalibrationRecord>& records) {
  Json list = Json::array();
  for (const auto& r : records) list.push_back(CalibrationJson(r));
  return Dump(Json{{"calibrations", std::move(list)}});
}

std::string EncodeModel(const storage::ModelVersion& model) {
  return Dump(ModelJson(model));
}

std::string EncodeModelList(const std::vector<storage::ModelVersion>& models) {
  Json list = Json::array();
  for (const auto& m : models) list.push_back(ModelJson(m));
  return Dump(Json{{"models", std::move(list)}});
}

std::string EncodeHealth(bool healthy) {
  if (healthy) return Dump(Json{{"status", "ok"}});
  return Dump(Json{{"status", "unavailable"},
                   {"error",
                    {{"code", "unavailable"},
                     {"message", "the database does not answer"},
                     {"field", nullptr}}}});
}

}  // namespace rollwear::api
