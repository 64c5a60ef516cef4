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
#include "api/json_scan.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::api {
namespace {

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

ApiError BadRequest(std::string code, std::string field, std::string message) {
  return ApiError{400, std::move(code), std::move(message), std::move(field)};
}

std::string Short(std::string_view s) {
  return std::string(s.size() <= 40 ? s : s.substr(0, 37)) +
         (s.size() <= 40 ? "" : "...");
}

// Typed, checked access to the members of one scanned object; the first
// broken rule is kept in *error with the member's JSON path. `list` and
// `element` name an element of the body's list ("passes", 1); element -1
// is the body itself.
class ObjectReader {
 public:
  ObjectReader(const ScannedObject& object, const ObjectShape& shape,
               ApiError* error, std::string_view list = "", int element = -1)
      : object_(object),
        shape_(shape),
        list_(list),
        element_(element),
        error_(error) {}

  // The JSON path of member `key` of this object.
  std::string Path(std::string_view key) const {
    std::string path;
    if (element_ >= 0) {
      path = std::string(list_) + "[" + std::to_string(element_) + "].";
    }
    return path += key;
  }

  bool Has(int i) const { return object_.members[i].kind != JsonKind::kAbsent; }

  // Member i, or null (and the error) when missing.
  const JsonValue* Get(int i) {
    if (Has(i)) return &object_.members[i];
    const std::string path = Path(shape_.members[i]);
    *error_ = BadRequest("missing_field", path, path + " is required");
    return nullptr;
  }

  bool WrongType(int i, const char* want, const JsonValue& got) {
    const std::string path = Path(shape_.members[i]);
    *error_ = BadRequest(
        "wrong_type", path,
        path + " must be " + want + ", got " + JsonKindName(got.kind));
    return false;
  }

  bool OutOfRange(std::string_view key, const std::string& rule) {
    const std::string path = Path(key);
    *error_ = BadRequest("out_of_range", path, path + " " + rule);
    return false;
  }

  bool Invalid(std::string_view key, const std::string& rule) {
    const std::string path = Path(key);
    *error_ = BadRequest("invalid_value", path, path + " " + rule);
    return false;
  }

  // A string of at most kMaxIdLength bytes.
  bool Text(int i, std::string* out) {
    std::string_view text;
    if (!String(i, "a string", &text)) return false;
    if (text.size() > kMaxIdLength) {
      return OutOfRange(
          shape_.members[i],
          "must be at most " + std::to_string(kMaxIdLength) + " bytes");
    }
    out->assign(text);
    return true;
  }

  // A JSON number (integer or not).
  bool Number(int i, double* out) {
    const JsonValue* v = Get(i);
    if (v == nullptr) return false;
    if (v->kind != JsonKind::kNumber) return WrongType(i, "a number", *v);
    *out = v->number;
    return true;
  }

  // A JSON integer (not 3.0 or 3.5) within [lo, hi].
  bool Integer(int i, int64_t lo, int64_t hi, int64_t* out) {
    const JsonValue* v = Get(i);
    if (v == nullptr) return false;
    if (v->kind != JsonKind::kNumber || !v->integer) {
      return WrongType(i, "an integer", *v);
    }
    if (v->above_int64) {
      return OutOfRange(shape_.members[i], "must be <= " + std::to_string(hi));
    }
    *out = v->as_int;
    if (*out < lo || *out > hi) {
      return OutOfRange(shape_.members[i], "must be an integer in [" +
                                               std::to_string(lo) + ", " +
                                               std::to_string(hi) + "], got " +
                                               std::to_string(*out));
    }
    return true;
  }

  bool Timestamp(int i, UnixSeconds* out) {
    std::string_view text;
    if (!String(i, "an ISO 8601 string", &text)) return false;
    if (!ParseTimestampView(text, out)) {
      return Invalid(shape_.members[i],
                     "must be an ISO 8601 timestamp with offset or Z, got '" +
                         Short(text) + "'");
    }
    return true;
  }

  bool Stand(int i, int* out) {
    std::string_view text;
    if (!String(i, "a string (F1..F7)", &text)) return false;
    *out = ParseStand(std::string(text));
    if (*out == 0) {
      return Invalid(shape_.members[i],
                     "must be a stand F1..F7, got '" + Short(text) + "'");
    }
    return true;
  }

  bool PositionOf(int i, Position* out) {
    std::string_view text;
    if (!String(i, "a string (top|bottom)", &text)) return false;
    if (!ParsePosition(std::string(text), out)) {
      return Invalid(shape_.members[i],
                     "must be top or bottom, got '" + Short(text) + "'");
    }
    return true;
  }

  // 0 or 1 (true/false accepted as well).
  bool Flag(int i, bool* out) {
    const JsonValue* v = Get(i);
    if (v == nullptr) return false;
    if (v->kind == JsonKind::kBoolean) {
      *out = v->boolean;
      return true;
    }
    if (v->kind != JsonKind::kNumber || !v->integer) {
      return WrongType(i, "0 or 1", *v);
    }
    if (v->above_int64 || (v->as_int != 0 && v->as_int != 1)) {
      return OutOfRange(shape_.members[i],
                        "must be 0 or 1, got " + std::string(v->text));
    }
    *out = v->as_int == 1;
    return true;
  }

  // The list member: an array of at most shape.max_elements elements.
  bool List(int i) {
    const JsonValue* v = Get(i);
    if (v == nullptr) return false;
    if (v->kind != JsonKind::kArray) return WrongType(i, "an array", *v);
    if (v->size > shape_.max_elements) {
      return OutOfRange(shape_.members[i],
                        "must have at most " +
                            std::to_string(shape_.max_elements) +
                            " elements, got " + std::to_string(v->size));
    }
    return true;
  }

  // Element e of the list member is an object.
  bool ElementIsObject(size_t e) {
    const JsonKind kind = object_.elements[e].kind;
    if (kind == JsonKind::kObject) return true;
    const std::string path = Path(shape_.members[shape_.list_member]) + "[" +
                             std::to_string(e) + "]";
    *error_ =
        BadRequest("wrong_type", path,
                   path + " must be an object, got " + JsonKindName(kind));
    return false;
  }

  // Control bodies: every member must be known; the first other one is
  // refused as unknown_field (a typo must not select a default).
  bool OnlyKnown() {
    if (object_.extras.empty()) return true;
    std::string names;
    for (std::string_view name : shape_.members) {
      names += (names.empty() ? "" : ", ") + std::string(name);
    }
    const std::string field = Path(object_.extras.front().first);
    *error_ =
        BadRequest("unknown_field", field,
                   "'" + Short(field) +
                       "' is not a field of this body (known: " + names + ")");
    return false;
  }

  // Data bodies: the extra members as ExtraFields (codec.h). `columns`:
  // the data format's other columns of the record's file, which are not
  // extra (a pass's coil_id, a coil's force_kn); `outer`: the coil's extra
  // members (null ones included), which a pass may not repeat.
  bool Extras(ExtraFields* out, std::span<const std::string_view> columns = {},
              std::span<const ExtraMember> outer = {});

  // Member `field` as sent, for a rule's ", got ..." (empty when it is no
  // finite number).
  std::string_view AsSent(std::string_view field) const {
    for (size_t i = 0; i < shape_.members.size(); ++i) {
      const JsonValue& v = object_.members[i];
      if (shape_.members[i] == field && v.kind == JsonKind::kNumber &&
          std::isfinite(v.number)) {
        return v.text;
      }
    }
    return {};
  }

 private:
  bool String(int i, const char* want, std::string_view* out) {
    const JsonValue* v = Get(i);
    if (v == nullptr) return false;
    if (v->kind != JsonKind::kString) return WrongType(i, want, *v);
    *out = v->text;
    return true;
  }

  const ScannedObject& object_;
  const ObjectShape& shape_;
  std::string_view list_;
  int element_;
  ApiError* error_;
};

bool ObjectReader::Extras(ExtraFields* out,
                          std::span<const std::string_view> columns,
                          std::span<const ExtraMember> outer) {
  if (object_.extras.size() > kMaxExtraFields) {
    return OutOfRange(object_.extras[kMaxExtraFields].first,
                      "is one extra field too many (at most " +
                          std::to_string(kMaxExtraFields) + " per object)");
  }
  for (const auto& [name, v] : object_.extras) {
    if (name.empty()) {
      return OutOfRange(name, "(an extra field) must have a name");
    }
    if (std::find(columns.begin(), columns.end(), name) != columns.end()) {
      return Invalid(name,
                     "is a column of the data format, not an extra field");
    }
    if (name.size() > kMaxIdLength) {
      return OutOfRange(name, "names an extra field longer than " +
                                  std::to_string(kMaxIdLength) + " bytes");
    }
    for (const auto& [coil_name, unused] : outer) {
      if (coil_name == name) {
        return Invalid(name, "is also an extra field of the coil");
      }
    }
    switch (v.kind) {
      case JsonKind::kNumber:
        if (!std::isfinite(v.number)) return OutOfRange(name, "must be finite");
        out->numeric.emplace_back(name, v.number);
        break;
      case JsonKind::kString:
        if (v.text.size() > kMaxIdLength) {
          return OutOfRange(name, "must be at most " +
                                      std::to_string(kMaxIdLength) + " bytes");
        }
        out->factor.emplace_back(name, v.text);
        break;
      case JsonKind::kBoolean:
        out->factor.emplace_back(name, v.boolean ? "true" : "false");
        break;
      case JsonKind::kNull:  // an empty cell
        break;
      default:
        *error_ = BadRequest("wrong_type", Path(name),
                             Path(name) +
                                 " is an extra field: it must be a number, "
                                 "string, boolean or null, got " +
                                 JsonKindName(v.kind));
        return false;
    }
  }
  out->Sort();
  return true;
}

// The first of `broken` (core/dataset/input_rules.h) as a 400 naming its
// JSON path (`readers[element]` for a list element, `body` else):
// invalid_value for a stand or roll position twice, out_of_range otherwise;
// a cited value is quoted as sent. True when `broken` is empty.
bool Admissible(const ObjectReader& body,
                const std::vector<ObjectReader>& elements,
                const RuleViolations& broken, ApiError* error) {
  if (broken.empty()) return true;
  const RuleViolation& v = broken.front();
  const ObjectReader& at =
      v.element >= 0 ? elements.at(static_cast<size_t>(v.element)) : body;
  const std::string path = at.Path(v.field);
  std::string message = path + " " + v.rule;
  if (v.cites_value) {
    // As sent, unless JSON cannot say it (1e999 reads as infinity).
    const std::string_view sent = at.AsSent(v.field);
    message += ", got " + (sent.empty() ? v.value : std::string(sent));
  }
  *error = BadRequest(
      v.kind == RuleKind::kDuplicate ? "invalid_value" : "out_of_range", path,
      std::move(message));
  return false;
}

// A control body may be empty (whitespace only): the defaults.
bool IsBlank(std::string_view body) {
  return body.find_first_not_of(" \t\r\n") == std::string_view::npos;
}

}  // namespace

bool DecodeRollChange(std::string_view body, int max_depth,
                      storage::RollChangeIn* out, ApiError* error) {
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
  return Admissible(
      r, rolls,
      RollChangeRules(out->campaign_id, storage::MountRecords(out->rolls)),
      error);
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
  return true;
}

bool DecodeMeasurement(std::string_view body, int max_depth,
                       storage::MeasurementIn* out, ApiError* error) {
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
  return Admissible(
      r, {},
      MeasurementRules(out->campaign_id, out->stand, out->position,
                       out->roll_id, out->wear_center_um),
      error);
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
    return r.OutOfRange("limit_um", "must be > 0 and at most " +
                                        std::to_string(static_cast<int>(
                                            storage::kMaxWearLimitUm)) +
                                        " µm, got " +
                                        std::string(scanned.members[kLimitUm]
                                                        .text.substr(0, 40)));
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
