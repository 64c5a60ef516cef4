// The answer bodies of docs/api.md (see codec.h).
#include <cmath>
#include <utility>

#include <nlohmann/json.hpp>

#include "api/codec.h"
#include "core/ann_model.h"
#include "core/dataset_io.h"
#include "storage/model_codec.h"

namespace rollwear::api {
namespace {

// Insertion-ordered objects: answers list their fields in the documented
// order.
using Json = nlohmann::ordered_json;

std::string Dump(const Json& j) {
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

const char* OutcomeName(storage::WriteOutcome o) {
  return o == storage::WriteOutcome::kCreated ? "created" : "unchanged";
}

Json TimeOrNull(UnixSeconds t) {
  return t == 0 ? Json(nullptr) : Json(FormatTimestamp(t));
}

Json FiniteOrNull(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

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

Json PositionJson(const storage::PositionWear& w) {
  return Json{
      {"stand", "F" + std::to_string(w.stand)},
      {"position", PositionName(w.position)},
      {"roll_id", w.roll_id},
      {"roll_type", w.roll_type},
      {"campaign_id", w.campaign_id},
      {"coils", w.coils},
      {"rolled_length_m", w.rolled_length_m},
      {"predicted_wear_um", w.predicted_wear_um},
      {"interval_um", Json::array({w.interval_lo_um, w.interval_hi_um})}};
}

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
      {"created_at", TimeOrNull(m.created_at)}};
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
  Json e{{"code", error.code},
         {"message", error.message},
         {"field", error.field.empty() ? Json(nullptr) : Json(error.field)}};
  return Dump(Json{{"error", e}});
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
  Json added = Json::array();
  for (const auto& a : outcome.added) {
    added.push_back({{"stand", "F" + std::to_string(a.stand)},
                     {"position", PositionName(a.position)},
                     {"roll_id", a.roll_id},
                     {"wear_um", a.wear_um},
                     {"predicted_wear_um", a.predicted_wear_um}});
  }
  Json j{{"coil_id", in.coil_id},
         {"campaign_id", in.campaign_id},
         {"outcome", OutcomeName(outcome.outcome)},
         {"added", std::move(added)}};
  if (model_version >= 0) j["model_version"] = model_version;
  return Dump(j);
}

std::string EncodeMeasurementAnswer(const storage::MeasurementIn& in,
                                    storage::WriteOutcome outcome) {
  return Dump(Json{{"campaign_id", in.campaign_id},
                   {"stand", "F" + std::to_string(in.stand)},
                   {"position", PositionName(in.position)},
                   {"outcome", OutcomeName(outcome)}});
}

std::string EncodeWear(const storage::WearSnapshot& snapshot) {
  Json positions = Json::array();
  for (const auto& p : snapshot.positions) positions.push_back(PositionJson(p));
  return Dump(Json{{"model_version", snapshot.model_version},
                   {"positions", std::move(positions)}});
}

std::string EncodePositionWear(const storage::PositionWear& wear,
                               int64_t model_version) {
  Json j = PositionJson(wear);
  j["model_version"] = model_version;
  return Dump(j);
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
