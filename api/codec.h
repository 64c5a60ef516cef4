// Internal to the api layer (included by api/*.cc only): JSON <-> storage
// types. Decoders check the body's nesting depth before parsing, parse
// without exceptions, check every field's presence and JSON type (integers
// are told apart from other numbers), then the record's rules
// (core/dataset/input_rules.h), and name a bad field by its JSON path
// ("passes[1].force_kn"). In a data body (roll change, campaign end, coil,
// measurement) unknown extra fields are ignored; a control body
// (calibration, diagnosis) refuses them.
// Encoders produce the answer bodies of docs/api.md. nlohmann/json.hpp is
// included by .cc files only.
//
// Thread-safety: stateless functions.
#ifndef ROLLWEAR_API_CODEC_H_
#define ROLLWEAR_API_CODEC_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/model/wear_law.h"
#include "storage/store_types.h"

namespace rollwear::api {

// Identifiers (campaign, coil, roll ids, labels) longer than this are
// refused; nothing in a mill comes close.
inline constexpr size_t kMaxIdLength = 200;
// A coil passes each stand at most once.
inline constexpr size_t kMaxPasses = kMaxStand;

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
bool DecodeRollChange(std::string_view body, int max_depth,
                      storage::RollChangeIn* out, ApiError* error);
bool DecodeCampaignEnd(std::string_view body, int max_depth,
                       UnixSeconds* ended_at, ApiError* error);
// TryDecodeCoilFast (api/coil_fast_decode.h) for the usual body, else
// DecodeCoilDom, which produces every error.
bool DecodeCoil(std::string_view body, int max_depth, storage::CoilIn* out,
                ApiError* error);
// DecodeCoil's general path: the body as an nlohmann DOM, read member by
// member. Declared for the tests that compare it with the fast path.
bool DecodeCoilDom(std::string_view body, int max_depth, storage::CoilIn* out,
                   ApiError* error);
bool DecodeMeasurement(std::string_view body, int max_depth,
                       storage::MeasurementIn* out, ApiError* error);
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
// (MillStore::ProposeModel).
struct DiagnosisRequest {
  bool adopt = false;
};
bool DecodeDiagnosisRequest(std::string_view body, int max_depth,
                            DiagnosisRequest* out, ApiError* error);

// Answer bodies.
std::string EncodeRollChangeAnswer(const storage::RollChangeIn& in,
                                   storage::WriteOutcome outcome);
std::string EncodeCampaignEndAnswer(const std::string& campaign_id,
                                    UnixSeconds ended_at,
                                    storage::WriteOutcome outcome);
std::string EncodeCoilAnswer(const storage::CoilIn& in,
                             const storage::CoilOutcome& outcome,
                             int64_t model_version);
std::string EncodeMeasurementAnswer(const storage::MeasurementIn& in,
                                    storage::WriteOutcome outcome);
std::string EncodeWear(const storage::WearSnapshot& snapshot);
std::string EncodePositionWear(const storage::PositionWear& wear,
                               int64_t model_version);
std::string EncodeCalibrationId(int64_t id);
std::string EncodeCalibration(const storage::CalibrationRecord& record);
std::string EncodeCalibrationList(
    const std::vector<storage::CalibrationRecord>& records);
std::string EncodeModel(const storage::ModelVersion& model);
std::string EncodeModelList(const std::vector<storage::ModelVersion>& models);
std::string EncodeHealth(bool healthy);

// Maximum nesting depth of arrays and objects in `body` (strings are
// skipped), without parsing it. Stops counting above `limit`.
int JsonNestingDepth(std::string_view body, int limit);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_CODEC_H_
