// Internal to the api layer (included by api/*.cc only): JSON <-> storage
// types. Every request body is decoded by one decoder: ScanBody
// (api/json_scan.h, simdjson On-Demand) reads and validates the whole
// document as JSON within the nesting limit (malformed JSON is refused
// before any field is looked at; a member twice in one object is refused);
// then
// each field's presence and JSON type are checked (integers are told apart
// from other numbers), then the record's rules
// (core/dataset/input_rules.h). A bad field is named by its JSON path
// ("passes[1].force_kn"). In a data body (roll change, coil and its passes,
// measurement) the members a body does not define are its extra fields,
// decoded into the record's ExtraFields (core/dataset/extra_fields.h; the
// rules are at Decode*); a campaign end ignores them; a control body
// (calibration, diagnosis) refuses them with unknown_field.
// Encoders produce the answer bodies of docs/api.md (api/json_writer.h for
// the hot ones, an nlohmann DOM for the rest; nlohmann/json.hpp and
// simdjson.h are included by .cc files only).
//
// Thread-safety: stateless functions (the decoders use a thread_local
// parser, api/json_scan.h).
#ifndef ROLLWEAR_API_CODEC_H_
#define ROLLWEAR_API_CODEC_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/model/wear_law.h"
#include "engine/wear_answers.h"
#include "storage/store_types.h"

namespace rollwear::api {

// Identifiers (campaign, coil, roll ids, labels) longer than this are
// refused; nothing in a mill comes close.
inline constexpr size_t kMaxIdLength = 200;
// A coil passes each stand at most once.
inline constexpr size_t kMaxPasses = kMaxStand;
// Extra fields per JSON object of a data body (a roll change, one of its
// rolls, a coil, one of its passes, a measurement); more are refused.
inline constexpr size_t kMaxExtraFields = 64;

// One error answer: HTTP status, snake_case code, one sentence, and the
// JSON path of the offending field (empty = null).
struct ApiError {
  int status = 0;
  std::string code;
  std::string message;
  std::string field;
};

// {"error": {"code", "message", "field"}}.
std::string EncodeError(const ApiError& error);

// Decoders: true and *out filled, or false and *error (status 400).
//
// Extra fields of a data body (each object's members the body does not
// define) go to that record's `extra` (RollChangeIn::extra: the campaign's;
// MountedRollIn::extra: the roll's; CoilIn::extra: the coil's own, which
// apply to each of its passes; PassIn::extra: the pass's;
// MeasurementIn::extra): a number (finite) is a numeric value, a string (at
// most kMaxIdLength bytes) or true/false ("true"/"false") a factor level,
// null an empty cell (not kept). Refused with the extra field's path: an
// object or array (wrong_type); an empty name, a name longer than
// kMaxIdLength bytes, a non-finite number, more than kMaxExtraFields extras
// in one object (out_of_range); a pass field that the coil has as well, the
// name of a column of the record's CSV file (a coil's force_kn, a pass's
// seq, a campaign's ended_at, a roll's campaign_id: invalid_value). Each
// list is sorted by name (ExtraFields::Sort), so member order does not
// matter.
bool DecodeRollChange(std::string_view body, int max_depth,
                      storage::RollChangeIn* out, ApiError* error);
// Ignores the body's other members (a campaign's extra fields come with its
// roll change).
bool DecodeCampaignEnd(std::string_view body, int max_depth,
                       UnixSeconds* ended_at, ApiError* error);
bool DecodeCoil(std::string_view body, int max_depth, storage::CoilIn* out,
                ApiError* error);
bool DecodeMeasurement(std::string_view body, int max_depth,
                       storage::MeasurementIn* out, ApiError* error);
// POST /v1/profiles (api/codec_profile.cc): {"campaign_id", "stand",
// "position", "roll_id", "measured_at", "points": [{"x_mm", "wear_um"}...]}
// with at most kMaxProfilePoints points; each point's fields are named by
// path ("points[3].x_mm"). Other members are ignored (a profile carries no
// extra fields). The point rules (at least one, on the barrel, finite,
// no x twice) are the store's (storage/validation.h), reported with the
// same paths.
inline constexpr size_t kMaxProfilePoints = 4096;
bool DecodeProfile(std::string_view body, int max_depth,
                   storage::ProfileIn* out, ApiError* error);
// An empty body (or "{}") selects the defaults.
// {"model": "ann"} asks for the recurrent network (option is ignored).
struct CalibrationRequest {
  WearLaw law = WearLaw::kWang;
  int option = 1;
  bool ann = false;
};
bool DecodeCalibrationRequest(std::string_view body, int max_depth,
                              CalibrationRequest* out, ApiError* error);
// POST /v1/diagnoses: optional {"adopt": true|false} (default false): when
// the diagnosis finds missing physics, propose its adopted model
// (engine::CalibrationRuns::Propose).
struct DiagnosisRequest {
  bool adopt = false;
};
bool DecodeDiagnosisRequest(std::string_view body, int max_depth,
                            DiagnosisRequest* out, ApiError* error);

// POST /v1/limits/{stand}/{position}: {"limit_um": number, "reason":
// string|null (optional)}; limit_um must be in (0, kMaxWearLimitUm]
// (out_of_range otherwise, field "limit_um"); other members unknown_field.
// Sets limit_um and reason only.
bool DecodeWearLimit(std::string_view body, int max_depth,
                     storage::WearLimitIn* out, ApiError* error);
// POST /v1/forecast: {"coils": [coil, ...]}, each coil decoded by
// DecodeCoil with the same rules; a bad field is named by its path in the
// body ("coils[3].passes[1].force_kn"). More than max_coils coils: 413
// too_many_elements; none: 400 out_of_range (api/codec_forecast.cc).
bool DecodeForecast(std::string_view body, int max_depth, size_t max_coils,
                    std::vector<storage::CoilIn>* out, ApiError* error);
// POST /v1/models/{version}/activate: {"reason": "<why>", "pin": true|
// false (default true)}; reason required, not blank, at most kMaxIdLength
// bytes.
struct ActivateRequest {
  std::string reason;
  bool pin = true;
};
bool DecodeActivateRequest(std::string_view body, int max_depth,
                           ActivateRequest* out, ApiError* error);

// Answer bodies.
std::string EncodeRollChangeAnswer(const storage::RollChangeIn& in,
                                   storage::WriteOutcome outcome);
std::string EncodeCampaignEndAnswer(const std::string& campaign_id,
                                    UnixSeconds ended_at,
                                    storage::WriteOutcome outcome);
std::string EncodeCoilAnswer(const storage::CoilIn& in,
                             const storage::CoilOutcome& outcome,
                             int64_t model_version);
// "suspect": in.suspect ("<kind>: <reason>"), null when plausible.
std::string EncodeMeasurementAnswer(const storage::MeasurementIn& in,
                                    storage::WriteOutcome outcome);
// {"campaign_id","stand","position","roll_id","points":N,"outcome"}.
std::string EncodeProfileAnswer(const storage::ProfileIn& in,
                                storage::WriteOutcome outcome);
// GET /v1/wear/{stand}/{position}/profile: {"stand","position","roll_id",
// "campaign_id","model_version","coils","centre_wear_um","shape":
// "calibrated"|"uncalibrated","coefficients":{beta2..alpha3}|null,
// "standard_errors":{...}|null,"residual_sd_um":number|null,"x_mm":[...],
// "predicted_wear_um":[...],"interval_um":[[lo,hi]...]}.
std::string EncodeWearProfile(const engine::ProfileWear& wear);
std::string EncodeWear(const engine::WearSnapshot& snapshot);
std::string EncodePositionWear(const engine::PositionWear& wear,
                               int64_t model_version);
std::string EncodeCalibrationId(int64_t id);
std::string EncodeCalibration(const storage::CalibrationRecord& record);
std::string EncodeCalibrationList(
    const std::vector<storage::CalibrationRecord>& records);
std::string EncodeModel(const storage::ModelVersion& model);
std::string EncodeModelList(const std::vector<storage::ModelVersion>& models);
std::string EncodeHealth(bool healthy);
// api/codec_forecast.cc: GET /v1/limits, one limit (the answer of POST
// /v1/limits/...), POST /v1/forecast.
std::string EncodeWearLimits(const std::vector<storage::WearLimit>& limits);
std::string EncodeWearLimit(const storage::WearLimit& limit);
std::string EncodeForecast(const engine::Forecast& forecast);
// codec_shop.cc: the model audit trail, rolls and stored diagnoses.
std::string EncodeModelHistory(
    const std::vector<storage::ModelPromotion>& history);
// With `factor`, also "wear_factor": {"value","interval":[lo,hi],"readings"}.
std::string EncodeRollLife(const storage::RollLife& life,
                           const std::optional<RollWearFactor>& factor = std::nullopt);
std::string EncodeRollInventory(const std::vector<storage::RollSummary>& rolls);
std::string EncodeDiagnosisList(
    const std::vector<storage::StoredDiagnosis>& diagnoses);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_CODEC_H_
