// The answer bodies of the roll shop's endpoints (docs/api.md "Rolls",
// "Models under control", "Stored diagnoses"): the model audit trail, a
// roll's life, the roll inventory and the list of stored diagnoses.
#include <string>
#include <vector>

#include "api/codec.h"
#include "api/codec_json_util.h"
#include "core/dataset/dataset.h"

namespace rollwear::api {

using codec_internal::Dump;
using codec_internal::FiniteOrNull;
using codec_internal::Json;
using codec_internal::TimeOrNull;

namespace {

Json OptionalUm(const std::optional<double>& v) {
  return v.has_value() ? FiniteOrNull(*v) : Json(nullptr);
}

Json SuspectOrNull(const std::string& suspect) {
  return suspect.empty() ? Json(nullptr) : Json(suspect);
}

}  // namespace

std::string EncodeModelHistory(
    const std::vector<storage::ModelPromotion>& history) {
  Json list = Json::array();
  for (const storage::ModelPromotion& p : history) {
    list.push_back(
        {{"version", p.version},
         {"previous_version",
          p.previous_version == 0 ? Json(nullptr) : Json(p.previous_version)},
         {"source", p.source},
         {"reason", p.reason},
         {"at", TimeOrNull(p.at)},
         {"pinned", p.pinned}});
  }
  return Dump(Json{{"history", std::move(list)}});
}

std::string EncodeRollLife(const storage::RollLife& life,
                           const std::optional<RollWearFactor>& factor) {
  Json mounts = Json::array();
  for (const storage::RollMountLife& m : life.mounts) {
    mounts.push_back(
        {{"campaign_id", m.campaign_id},
         {"stand", StandName(m.stand)},
         {"position", PositionName(m.position)},
         {"started_at", TimeOrNull(m.started_at)},
         {"ended_at", m.ended_at ? TimeOrNull(*m.ended_at) : Json(nullptr)},
         {"running", !m.ended_at.has_value()},
         {"diameter_mm", m.diameter_mm},
         {"hardness_hb", m.hardness_hb},
         {"coils", m.coils},
         {"rolled_length_m", m.rolled_length_m},
         {"rolled_km", m.rolled_length_m / 1000.0},
         {"predicted_wear_um", FiniteOrNull(m.predicted_wear_um)},
         {"measured_wear_um", OptionalUm(m.measured_um)},
         {"expected_reading_um", OptionalUm(m.expected_reading_um)},
         {"suspect", SuspectOrNull(m.measured_suspect)}});
  }
  Json out{{"roll_id", life.roll_id},
           {"roll_type", life.roll_type},
           {"model_version", life.model_version},
           {"mounts", std::move(mounts)}};
  if (factor.has_value()) {
    out["wear_factor"] = {{"value", factor->value},
                          {"interval", {factor->lo, factor->hi}},
                          {"readings", factor->readings}};
  }
  return Dump(out);
}

std::string EncodeRollInventory(
    const std::vector<storage::RollSummary>& rolls) {
  Json list = Json::array();
  for (const storage::RollSummary& r : rolls) {
    list.push_back(
        {{"roll_id", r.roll_id},
         {"roll_type", r.roll_type},
         {"last_diameter_mm", r.last_diameter_mm},
         {"campaigns", r.campaigns},
         {"total_rolled_km", r.total_rolled_m / 1000.0},
         {"last_measured_wear_um", OptionalUm(r.last_measured_um)},
         {"last_measured_suspect", SuspectOrNull(r.last_measured_suspect)},
         {"mounted", r.mounted},
         {"mounted_at", !r.mounted
                            ? Json(nullptr)
                            : Json{{"campaign_id", r.campaign_id},
                                   {"stand", StandName(r.stand)},
                                   {"position", PositionName(r.position)}}}});
  }
  return Dump(Json{{"rolls", std::move(list)}});
}

std::string EncodeDiagnosisList(
    const std::vector<storage::StoredDiagnosis>& diagnoses) {
  Json list = Json::array();
  for (const storage::StoredDiagnosis& d : diagnoses) {
    list.push_back(
        {{"id", d.id},
         {"status", d.status},
         {"adopt", d.adopt},
         {"queued_at", TimeOrNull(d.queued_at)},
         {"started_at", TimeOrNull(d.started_at)},
         {"finished_at", TimeOrNull(d.finished_at)},
         {"verdict", d.verdict.empty() ? Json(nullptr) : Json(d.verdict)},
         {"calibration_id",
          d.calibration_id == 0 ? Json(nullptr) : Json(d.calibration_id)},
         {"message", d.message}});
  }
  return Dump(Json{{"diagnoses", std::move(list)}});
}

}  // namespace rollwear::api
