// Request bodies: nesting check, parsing and field validation (see
// codec.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/codec.h"
#include "api/coil_fast_decode.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::api {
namespace {

// Insertion-ordered objects: answers list their fields in the documented
// order.
using Json = nlohmann::ordered_json;

constexpr size_t kMaxRolls = kNumRollPositionSlots;

std::string Dump(const Json& j) {
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

ApiError BadRequest(std::string code, std::string field, std::string message) {
  return ApiError{400, std::move(code), std::move(message), std::move(field)};
}

// Parses `body` into an object; malformed JSON, too deep nesting and a
// non-object body are 400s.
bool ParseObject(std::string_view body, int max_depth, Json* out,
                 ApiError* error) {
  if (JsonNestingDepth(body, max_depth) > max_depth) {
    *error = BadRequest("nesting_too_deep", "",
                        "the body nests arrays/objects deeper than " +
                            std::to_string(max_depth) + " levels");
    return false;
  }
  try {
    *out = Json::parse(body.begin(), body.end());
  } catch (const Json::exception& e) {
    std::string what = e.what();
    const size_t close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
    *error = BadRequest("malformed_json", "", "malformed JSON: " + what);
    return false;
  }
  if (!out->is_object()) {
    *error = BadRequest(
        "wrong_type", "",
        std::string("the body must be a JSON object, got ") + out->type_name());
    return false;
  }
  return true;
}

std::string Join(const std::string& path, const char* key) {
  return path.empty() ? std::string(key) : path + "." + key;
}

// Typed, checked access to the members of one JSON object; the first broken
// rule is kept in *error with the member's JSON path.
class ObjectReader {
 public:
  ObjectReader(const Json& object, std::string path, ApiError* error)
      : object_(object), path_(std::move(path)), error_(error) {}

  // The member, or null (and the error) when missing.
  const Json* Get(const char* key) {
    auto it = object_.find(key);
    if (it == object_.end()) {
      *error_ = BadRequest("missing_field", Join(path_, key),
                           Join(path_, key) + " is required");
      return nullptr;
    }
    return &*it;
  }

  bool WrongType(const char* key, const char* want, const Json& got) {
    *error_ = BadRequest(
        "wrong_type", Join(path_, key),
        Join(path_, key) + " must be " + want + ", got " + got.type_name());
    return false;
  }

  bool OutOfRange(const char* key, const std::string& rule) {
    *error_ = BadRequest("out_of_range", Join(path_, key),
                         Join(path_, key) + " " + rule);
    return false;
  }

  bool Invalid(const char* key, const std::string& rule) {
    *error_ = BadRequest("invalid_value", Join(path_, key),
                         Join(path_, key) + " " + rule);
    return false;
  }

  // A string of at most kMaxIdLength bytes.
  bool Text(const char* key, std::string* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (!v->is_string()) return WrongType(key, "a string", *v);
    const auto& s = v->get_ref<const std::string&>();
    if (s.size() > kMaxIdLength) {
      return OutOfRange(
          key, "must be at most " + std::to_string(kMaxIdLength) + " bytes");
    }
    *out = s;
    return true;
  }

  // A JSON number (integer or not).
  bool Number(const char* key, double* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (!v->is_number()) return WrongType(key, "a number", *v);
    *out = v->get<double>();
    return true;
  }

  // A JSON integer (not 3.0 or 3.5) within [lo, hi].
  bool Integer(const char* key, int64_t lo, int64_t hi, int64_t* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (!v->is_number_integer()) return WrongType(key, "an integer", *v);
    if (v->is_number_unsigned() &&
        v->get<uint64_t>() > static_cast<uint64_t>(INT64_MAX)) {
      return OutOfRange(key, "must be <= " + std::to_string(hi));
    }
    *out = v->get<int64_t>();
    if (*out < lo || *out > hi) {
      return OutOfRange(key, "must be an integer in [" + std::to_string(lo) +
                                 ", " + std::to_string(hi) + "], got " +
                                 std::to_string(*out));
    }
    return true;
  }

  bool Timestamp(const char* key, UnixSeconds* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (!v->is_string()) return WrongType(key, "an ISO 8601 string", *v);
    if (!ParseTimestamp(v->get_ref<const std::string&>(), out)) {
      return Invalid(key,
                     "must be an ISO 8601 timestamp with offset or Z, got '" +
                         Short(v->get_ref<const std::string&>()) + "'");
    }
    return true;
  }

  bool Stand(const char* key, int* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (!v->is_string()) return WrongType(key, "a string (F1..F7)", *v);
    *out = ParseStand(v->get_ref<const std::string&>());
    if (*out == 0) {
      return Invalid(key, "must be a stand F1..F7, got '" +
                              Short(v->get_ref<const std::string&>()) + "'");
    }
    return true;
  }

  bool PositionOf(const char* key, Position* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (!v->is_string()) return WrongType(key, "a string (top|bottom)", *v);
    if (!ParsePosition(v->get_ref<const std::string&>(), out)) {
      return Invalid(key, "must be top or bottom, got '" +
                              Short(v->get_ref<const std::string&>()) + "'");
    }
    return true;
  }

  // 0 or 1 (true/false accepted as well).
  bool Flag(const char* key, bool* out) {
    const Json* v = Get(key);
    if (v == nullptr) return false;
    if (v->is_boolean()) {
      *out = v->get<bool>();
      return true;
    }
    if (!v->is_number_integer()) return WrongType(key, "0 or 1", *v);
    const int64_t n = v->get<int64_t>();
    if (n != 0 && n != 1) {
      return OutOfRange(key, "must be 0 or 1, got " + std::to_string(n));
    }
    *out = n == 1;
    return true;
  }

  // An array of at most `max` elements.
  const Json* Array(const char* key, size_t max) {
    const Json* v = Get(key);
    if (v == nullptr) return nullptr;
    if (!v->is_array()) {
      WrongType(key, "an array", *v);
      return nullptr;
    }
    if (v->size() > max) {
      OutOfRange(key, "must have at most " + std::to_string(max) +
                          " elements, got " + std::to_string(v->size()));
      return nullptr;
    }
    return v;
  }

  // Control bodies: every member must be one of `known`; the first other
  // one is refused as unknown_field (a typo must not select a default).
  bool OnlyKnown(std::initializer_list<std::string_view> known) {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (std::find(known.begin(), known.end(), it.key()) != known.end()) {
        continue;
      }
      std::string names;
      for (std::string_view name : known) {
        names += (names.empty() ? "" : ", ") + std::string(name);
      }
      const std::string field = Join(path_, it.key().c_str());
      *error_ = BadRequest(
          "unknown_field", field,
          "'" + Short(field) +
              "' is not a field of this body (known: " + names + ")");
      return false;
    }
    return true;
  }

  const std::string& path() const { return path_; }

 private:
  static std::string Short(const std::string& s) {
    return s.size() <= 40 ? s : s.substr(0, 37) + "...";
  }

  const Json& object_;
  std::string path_;
  ApiError* error_;
};

// Element i of array `key` as an object reader.
bool ElementObject(const Json& array, const char* key, size_t i,
                   ApiError* error) {
  if (array[i].is_object()) return true;
  const std::string path = std::string(key) + "[" + std::to_string(i) + "]";
  *error = BadRequest("wrong_type", path,
                      path + " must be an object, got " + array[i].type_name());
  return false;
}

std::string ElementPath(const char* key, size_t i) {
  return std::string(key) + "[" + std::to_string(i) + "]";
}

// The first of `broken` (core/dataset/input_rules.h) as a 400 naming its
// JSON path (elements of `list`): invalid_value for a stand or roll position
// twice, out_of_range otherwise; a cited value is quoted as sent. True when
// `broken` is empty.
bool Admissible(const Json& body, const char* list,
                const RuleViolations& broken, ApiError* error) {
  if (broken.empty()) return true;
  const RuleViolation& v = broken.front();
  const Json* object = &body;
  std::string path = v.field;
  if (v.element >= 0) {
    object = &body.at(list).at(static_cast<size_t>(v.element));
    path = ElementPath(list, static_cast<size_t>(v.element)) + "." + v.field;
  }
  std::string message = path + " " + v.rule;
  if (v.cites_value) {
    // As sent, unless JSON cannot say it (1e999 reads as infinity).
    auto it = object->find(v.field);
    const bool as_sent = it != object->end() &&
                         (!it->is_number() || std::isfinite(it->get<double>()));
    message += ", got " + (as_sent ? Dump(*it) : v.value);
  }
  *error = BadRequest(
      v.kind == RuleKind::kDuplicate ? "invalid_value" : "out_of_range", path,
      std::move(message));
  return false;
}

}  // namespace

int JsonNestingDepth(std::string_view body, int limit) {
  int depth = 0, max_depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < body.size(); ++i) {
    const char c = body[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        max_depth = depth;
        if (max_depth > limit) return max_depth;
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return max_depth;
}

bool DecodeRollChange(std::string_view body, int max_depth,
                      storage::RollChangeIn* out, ApiError* error) {
  Json j;
  if (!ParseObject(body, max_depth, &j, error)) return false;
  ObjectReader r(j, "", error);
  if (!r.Text("campaign_id", &out->campaign_id) ||
      !r.Timestamp("started_at", &out->started_at)) {
    return false;
  }
  const Json* rolls = r.Array("rolls", kMaxRolls);
  if (rolls == nullptr) return false;
  for (size_t i = 0; i < rolls->size(); ++i) {
    if (!ElementObject(*rolls, "rolls", i, error)) return false;
    ObjectReader e((*rolls)[i], ElementPath("rolls", i), error);
    storage::MountedRollIn m;
    if (!e.Stand("stand", &m.stand) || !e.PositionOf("position", &m.position) ||
        !e.Text("roll_id", &m.roll_id) || !e.Text("roll_type", &m.roll_type) ||
        !e.Number("diameter_mm", &m.diameter_mm) ||
        !e.Number("hardness_hb", &m.hardness_hb)) {
      return false;
    }
    out->rolls.push_back(std::move(m));
  }
  return Admissible(
      j, "rolls",
      RollChangeRules(out->campaign_id, storage::MountRecords(out->rolls)),
      error);
}

bool DecodeCampaignEnd(std::string_view body, int max_depth,
                       UnixSeconds* ended_at, ApiError* error) {
  Json j;
  if (!ParseObject(body, max_depth, &j, error)) return false;
  ObjectReader r(j, "", error);
  return r.Timestamp("ended_at", ended_at);
}

bool DecodeCoil(std::string_view body, int max_depth, storage::CoilIn* out,
                ApiError* error) {
  return TryDecodeCoilFast(body, max_depth, out) ||
         DecodeCoilDom(body, max_depth, out, error);
}

bool DecodeCoilDom(std::string_view body, int max_depth, storage::CoilIn* out,
                   ApiError* error) {
  Json j;
  if (!ParseObject(body, max_depth, &j, error)) return false;
  ObjectReader r(j, "", error);
  int64_t seq = 0;
  if (!r.Text("coil_id", &out->coil_id) ||
      !r.Text("campaign_id", &out->campaign_id) ||
      !r.Integer("seq", INT64_MIN, INT64_MAX, &seq) ||
      !r.Timestamp("rolled_at", &out->rolled_at) ||
      !r.Text("grade", &out->grade)) {
    return false;
  }
  const Json* passes = r.Array("passes", kMaxPasses);
  if (passes == nullptr) return false;
  for (size_t i = 0; i < passes->size(); ++i) {
    if (!ElementObject(*passes, "passes", i, error)) return false;
    ObjectReader e((*passes)[i], ElementPath("passes", i), error);
    storage::PassIn p;
    if (!e.Stand("stand", &p.stand) || !e.Number("force_kn", &p.force_kn) ||
        !e.Number("width_mm", &p.width_mm) ||
        !e.Number("length_m", &p.length_m) ||
        !e.Number("entry_thickness_mm", &p.entry_thickness_mm) ||
        !e.Number("exit_thickness_mm", &p.exit_thickness_mm) ||
        !e.Number("temperature_c", &p.temperature_c) ||
        !e.Number("speed_mps", &p.speed_mps) ||
        !e.Flag("lubrication", &p.lubrication) ||
        !e.Number("shift_mm", &p.shift_mm)) {
      return false;
    }
    out->passes.push_back(p);
  }
  if (!Admissible(j, "passes",
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
  Json j;
  if (!ParseObject(body, max_depth, &j, error)) return false;
  ObjectReader r(j, "", error);
  if (!r.Text("campaign_id", &out->campaign_id) ||
      !r.Stand("stand", &out->stand) ||
      !r.PositionOf("position", &out->position) ||
      !r.Text("roll_id", &out->roll_id) ||
      !r.Timestamp("measured_at", &out->measured_at) ||
      !r.Number("wear_center_um", &out->wear_center_um)) {
    return false;
  }
  return Admissible(
      j, "",
      MeasurementRules(out->campaign_id, out->stand, out->position,
                       out->roll_id, out->wear_center_um),
      error);
}

bool DecodeCalibrationRequest(std::string_view body, int max_depth,
                              CalibrationRequest* out, ApiError* error) {
  size_t first = body.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return true;  // empty: defaults
  Json j;
  if (!ParseObject(body, max_depth, &j, error)) return false;
  ObjectReader r(j, "", error);
  if (!r.OnlyKnown({"model", "option"})) return false;
  if (j.contains("model")) {
    std::string model;
    if (!r.Text("model", &model)) return false;
    // docs/api.md: an empty string is out_of_range, as for every field.
    if (model.empty()) return r.OutOfRange("model", "must not be empty");
    out->ann = model == storage::kAnnModelName;
    if (!out->ann && !ParseWearLaw(model, &out->law)) {
      return r.Invalid("model", "must be wang, nikitenko, cao or ann, got '" +
                                    model.substr(0, 40) + "'");
    }
  }
  if (j.contains("option")) {
    int64_t option = 0;
    if (!r.Integer("option", 1, 3, &option)) return false;
    out->option = static_cast<int>(option);
  }
  return true;
}

bool DecodeDiagnosisRequest(std::string_view body, int max_depth,
                            DiagnosisRequest* out, ApiError* error) {
  size_t first = body.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return true;  // empty: defaults
  Json j;
  if (!ParseObject(body, max_depth, &j, error)) return false;
  ObjectReader r(j, "", error);
  if (!r.OnlyKnown({"adopt"})) return false;
  if (j.contains("adopt") && !r.Flag("adopt", &out->adopt)) return false;
  return true;
}

}  // namespace rollwear::api
