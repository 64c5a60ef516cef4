#include "tests/api/codec_reference.h"

#include <optional>
#include <utility>

#include <nlohmann/json.hpp>

namespace rollwear::api::reference {
namespace {

using Json = nlohmann::ordered_json;

std::string Dump(const Json& j) {
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

const char* OutcomeName(storage::WriteOutcome o) {
  return o == storage::WriteOutcome::kCreated ? "created" : "unchanged";
}

Json Optional(const std::optional<double>& v) {
  return v ? Json(*v) : Json(nullptr);
}

Json PositionJson(const engine::PositionWear& w) {
  const std::optional<RemainingLife>& r = w.remaining;
  Json j = Json{
      {"stand", "F" + std::to_string(w.stand)},
      {"position", PositionName(w.position)},
      {"roll_id", w.roll_id},
      {"roll_type", w.roll_type},
      {"campaign_id", w.campaign_id},
      {"coils", w.coils},
      {"rolled_length_m", w.rolled_length_m},
      {"predicted_wear_um", w.predicted_wear_um},
      {"interval_um", Json::array({w.interval_lo_um, w.interval_hi_um})}};
  j["wear_limit_um"] = Optional(w.wear_limit_um);
  j["remaining_length_m"] = r ? Json(r->length_m) : Json(nullptr);
  j["remaining_coils"] = r ? Json(r->coils) : Json(nullptr);
  j["remaining_length_interval_m"] =
      r ? Json::array({r->length_lo_m, Optional(r->length_hi_m)})
        : Json(nullptr);
  j["remaining_coils_interval"] =
      r ? Json::array({r->coils_lo, Optional(r->coils_hi)}) : Json(nullptr);
  return j;
}

}  // namespace

std::string EncodeError(const ApiError& error) {
  Json e{{"code", error.code},
         {"message", error.message},
         {"field", error.field.empty() ? Json(nullptr) : Json(error.field)}};
  return Dump(Json{{"error", e}});
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

std::string EncodeWear(const engine::WearSnapshot& snapshot) {
  Json positions = Json::array();
  for (const auto& p : snapshot.positions) positions.push_back(PositionJson(p));
  return Dump(Json{{"model_version", snapshot.model_version},
                   {"positions", std::move(positions)}});
}

std::string EncodePositionWear(const engine::PositionWear& wear,
                               int64_t model_version) {
  Json j = PositionJson(wear);
  j["model_version"] = model_version;
  return Dump(j);
}

std::string DumpString(const std::string& value) { return Dump(Json(value)); }

std::string DumpDouble(double value) { return Dump(Json(value)); }

}  // namespace rollwear::api::reference
