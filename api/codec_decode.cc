// Request bodies: the members of each body (ScanBody, api/json_scan.h),
// then each field's presence and JSON type, its extra fields, and the
// record's rules (core/dataset/input_rules.h) - see codec.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/codec.h"
#include "api/codec_reader.h"
#include "api/json_scan.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::api {
namespace {

using codec_internal::Admissible;
using codec_internal::ObjectReader;

constexpr size_t kMaxRolls = kNumRollPositionSlots;

// The members of each body, in the order their errors are reported (a
// body with two bad fields names the first of this list).
enum RollMember {
  kRollStand,
  kRollPosition,
  kRollId,
  kRollType,
  kDiameter,
  kHardness
};
constexpr std::string_view kRollMembers[] = {
    "stand", "position", "roll_id", "roll_type", "diameter_mm", "hardness_hb"};
constexpr ObjectShape kRollShape{kRollMembers};
enum RollChangeMember { kRcCampaignId, kRcStartedAt, kRcRolls };
constexpr std::string_view kRollChangeMembers[] = {"campaign_id", "started_at",
                                                   "rolls"};
// The columns of campaigns.csv and mounts.csv that these bodies do not
// carry: not names of extra fields.
constexpr std::string_view kCampaignOtherColumns[] = {"ended_at"};
constexpr std::string_view kMountOtherColumns[] = {"campaign_id"};
constexpr ObjectShape kRollChangeShape{kRollChangeMembers, kRcRolls,
                                       &kRollShape, kMaxRolls};

enum CampaignEndMember { kEndedAt };
constexpr std::string_view kCampaignEndMembers[] = {"ended_at"};
constexpr ObjectShape kCampaignEndShape{kCampaignEndMembers};

enum PassMember {
  kStand,
  kForce,
  kWidth,
  kLength,
  kEntryThickness,
  kExitThickness,
  kTemperature,
  kSpeed,
  kLubrication,
  kShift
};
constexpr std::string_view kPassMembers[] = {
    "stand",         "force_kn",           "width_mm",
    "length_m",      "entry_thickness_mm", "exit_thickness_mm",
    "temperature_c", "speed_mps",          "lubrication",
    "shift_mm"};
constexpr ObjectShape kPassShape{kPassMembers};
enum CoilMember { kCoilId, kCoilCampaignId, kSeq, kRolledAt, kGrade, kPasses };
constexpr std::string_view kCoilMembers[] = {
    "coil_id", "campaign_id", "seq", "rolled_at", "grade", "passes"};
constexpr ObjectShape kCoilShape{kCoilMembers, kPasses, &kPassShape,
                                 kMaxPasses};

enum MeasurementMember {
  kMCampaignId,
  kMStand,
  kMPosition,
  kMRollId,
  kMeasuredAt,
  kWear
};
constexpr std::string_view kMeasurementMembers[] = {
    "campaign_id", "stand",       "position",
    "roll_id",     "measured_at", "wear_center_um"};
constexpr ObjectShape kMeasurementShape{kMeasurementMembers};

enum CalibrationMember { kModel, kOption };
constexpr std::string_view kCalibrationMembers[] = {"model", "option"};
constexpr ObjectShape kCalibrationShape{kCalibrationMembers};
enum DiagnosisMember { kAdopt };
constexpr std::string_view kDiagnosisMembers[] = {"adopt"};
constexpr ObjectShape kDiagnosisShape{kDiagnosisMembers};
enum WearLimitMember { kLimitUm, kLimitReason };
constexpr std::string_view kWearLimitMembers[] = {"limit_um", "reason"};
constexpr ObjectShape kWearLimitShape{kWearLimitMembers};
enum ActivateMember { kReason, kPin };
constexpr std::string_view kActivateMembers[] = {"reason", "pin"};
constexpr ObjectShape kActivateShape{kActivateMembers};

// A control body may be empty (whitespace only): the defaults.
bool IsBlank(std::string_view body) {
  return body.find_first_not_of(" \t\r\n") == std::string_view::npos;
}

}  // namespace

bool DecodeRollChange(std::string_view body, int max_depth,
                      storage::RollChangeIn* out, ApiError* error) {
  out->rules_checked = false;  // until this decode's rules hold
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kRollChangeShape, &scanned, error)) {
    return false;
  }
  ObjectReader r(scanned, kRollChangeShape, error);
  if (!r.Text(kRcCampaignId, &out->campaign_id) ||
      !r.Timestamp(kRcStartedAt, &out->started_at) || !r.List(kRcRolls) ||
      !r.Extras(&out->extra, kCampaignOtherColumns)) {
    return false;
  }
  std::vector<ObjectReader> rolls;
  rolls.reserve(scanned.elements.size());
  for (size_t i = 0; i < scanned.elements.size(); ++i) {
    if (!r.ElementIsObject(i)) return false;
    ObjectReader& e = rolls.emplace_back(scanned.elements[i], kRollShape, error,
                                         "rolls", static_cast<int>(i));
    storage::MountedRollIn m;
    if (!e.Stand(kRollStand, &m.stand) ||
        !e.PositionOf(kRollPosition, &m.position) ||
        !e.Text(kRollId, &m.roll_id) || !e.Text(kRollType, &m.roll_type) ||
        !e.Number(kDiameter, &m.diameter_mm) ||
        !e.Number(kHardness, &m.hardness_hb) ||
        !e.Extras(&m.extra, kMountOtherColumns)) {
      return false;
    }
    out->rolls.push_back(std::move(m));
  }
  out->rules_checked = Admissible(
      r, rolls,
      RollChangeRules(out->campaign_id, storage::MountRecords(out->rolls)),
      error);
  return out->rules_checked;
}

bool DecodeCampaignEnd(std::string_view body, int max_depth,
                       UnixSeconds* ended_at, ApiError* error) {
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kCampaignEndShape, &scanned, error)) {
    return false;
  }
  // Other members are ignored (docs/api.md): a campaign's extra fields come
  // with its roll change.
  return ObjectReader(scanned, kCampaignEndShape, error)
      .Timestamp(kEndedAt, ended_at);
}

bool DecodeCoil(std::string_view body, int max_depth, storage::CoilIn* out,
                ApiError* error) {
  out->rules_checked = false;  // until this decode's rules hold
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kCoilShape, &scanned, error)) return false;
  ObjectReader r(scanned, kCoilShape, error);
  int64_t seq = 0;
  if (!r.Text(kCoilId, &out->coil_id) ||
      !r.Text(kCoilCampaignId, &out->campaign_id) ||
      !r.Integer(kSeq, INT64_MIN, INT64_MAX, &seq) ||
      !r.Timestamp(kRolledAt, &out->rolled_at) ||
      !r.Text(kGrade, &out->grade) || !r.List(kPasses) ||
      !r.Extras(&out->extra, kPassMembers)) {
    return false;
  }
  std::vector<ObjectReader> passes;
  passes.reserve(scanned.elements.size());
  out->passes.reserve(scanned.elements.size());
  for (size_t i = 0; i < scanned.elements.size(); ++i) {
    if (!r.ElementIsObject(i)) return false;
    ObjectReader& e = passes.emplace_back(scanned.elements[i], kPassShape,
                                          error, "passes", static_cast<int>(i));
    storage::PassIn& p = out->passes.emplace_back();
    if (!e.Stand(kStand, &p.stand) || !e.Number(kForce, &p.force_kn) ||
        !e.Number(kWidth, &p.width_mm) || !e.Number(kLength, &p.length_m) ||
        !e.Number(kEntryThickness, &p.entry_thickness_mm) ||
        !e.Number(kExitThickness, &p.exit_thickness_mm) ||
        !e.Number(kTemperature, &p.temperature_c) ||
        !e.Number(kSpeed, &p.speed_mps) ||
        !e.Flag(kLubrication, &p.lubrication) ||
        !e.Number(kShift, &p.shift_mm) ||
        !e.Extras(&p.extra, kCoilMembers, scanned.extras)) {
      return false;
    }
  }
  if (!Admissible(r, passes,
                  CoilRules(out->coil_id, out->campaign_id, seq, out->grade,
                            out->passes),
                  error)) {
    return false;
  }
  out->seq = static_cast<int>(seq);
  out->rules_checked = true;  // CoilRules held on these fields (seq above)
  return true;
}

bool DecodeMeasurement(std::string_view body, int max_depth,
                       storage::MeasurementIn* out, ApiError* error) {
  out->rules_checked = false;  // until this decode's rules hold
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kMeasurementShape, &scanned, error)) {
    return false;
  }
  ObjectReader r(scanned, kMeasurementShape, error);
  if (!r.Text(kMCampaignId, &out->campaign_id) ||
      !r.Stand(kMStand, &out->stand) ||
      !r.PositionOf(kMPosition, &out->position) ||
      !r.Text(kMRollId, &out->roll_id) ||
      !r.Timestamp(kMeasuredAt, &out->measured_at) ||
      !r.Number(kWear, &out->wear_center_um) || !r.Extras(&out->extra)) {
    return false;
  }
  out->rules_checked =
      Admissible(r, {},
                 MeasurementRules(out->campaign_id, out->stand, out->position,
                                  out->roll_id, out->wear_center_um),
                 error);
  return out->rules_checked;
}

bool DecodeCalibrationRequest(std::string_view body, int max_depth,
                              CalibrationRequest* out, ApiError* error) {
  if (IsBlank(body)) return true;
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kCalibrationShape, &scanned, error)) {
    return false;
  }
  ObjectReader r(scanned, kCalibrationShape, error);
  if (!r.OnlyKnown()) return false;
  if (r.Has(kModel)) {
    std::string model;
    if (!r.Text(kModel, &model)) return false;
    // docs/api.md: an empty string is out_of_range, as for every field.
    if (model.empty()) return r.OutOfRange("model", "must not be empty");
    out->ann = model == storage::kAnnModelName;
    if (!out->ann && !ParseWearLaw(model, &out->law)) {
      return r.Invalid("model", "must be wang, nikitenko, cao or ann, got '" +
                                    model.substr(0, 40) + "'");
    }
  }
  if (r.Has(kOption)) {
    int64_t option = 0;
    if (!r.Integer(kOption, 1, 3, &option)) return false;
    out->option = static_cast<int>(option);
  }
  return true;
}

bool DecodeDiagnosisRequest(std::string_view body, int max_depth,
                            DiagnosisRequest* out, ApiError* error) {
  if (IsBlank(body)) return true;
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kDiagnosisShape, &scanned, error)) {
    return false;
  }
  ObjectReader r(scanned, kDiagnosisShape, error);
  return r.OnlyKnown() && (!r.Has(kAdopt) || r.Flag(kAdopt, &out->adopt));
}

bool DecodeWearLimit(std::string_view body, int max_depth,
                     storage::WearLimitIn* out, ApiError* error) {
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kWearLimitShape, &scanned, error)) {
    return false;
  }
  ObjectReader r(scanned, kWearLimitShape, error);
  if (!r.OnlyKnown() || !r.Number(kLimitUm, &out->limit_um)) return false;
  if (!(out->limit_um > 0) || !(out->limit_um <= storage::kMaxWearLimitUm)) {
    return r.OutOfRange(
        "limit_um",
        "must be > 0 and at most " +
            std::to_string(static_cast<int>(storage::kMaxWearLimitUm)) +
            " µm, got " +
            std::string(scanned.members[kLimitUm].text.substr(0, 40)));
  }
  out->reason.clear();
  return !r.Has(kLimitReason) ||
         scanned.members[kLimitReason].kind == JsonKind::kNull ||
         r.Text(kLimitReason, &out->reason);
}

bool DecodeActivateRequest(std::string_view body, int max_depth,
                           ActivateRequest* out, ApiError* error) {
  ScannedObject scanned;
  if (!ScanBody(IsBlank(body) ? std::string_view("{}") : body, max_depth,
                kActivateShape, &scanned, error)) {
    return false;
  }
  ObjectReader r(scanned, kActivateShape, error);
  if (!r.OnlyKnown() || !r.Text(kReason, &out->reason)) return false;
  if (out->reason.find_first_not_of(" \t\r\n") == std::string::npos) {
    return r.OutOfRange("reason", "must not be empty");
  }
  return !r.Has(kPin) || r.Flag(kPin, &out->pin);
}

}  // namespace rollwear::api
