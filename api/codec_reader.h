// Internal to api/codec_*.cc: typed, checked reading of a scanned request
// body (api/json_scan.h) - ObjectReader - and the translation of a record's
// broken rules (core/dataset/input_rules.h) into a 400 naming the JSON path.
//
// Thread-safety: an ObjectReader is used by one thread; the rest is pure.
#ifndef ROLLWEAR_API_CODEC_READER_H_
#define ROLLWEAR_API_CODEC_READER_H_

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

namespace rollwear::api::codec_internal {

inline ApiError BadRequest(std::string code, std::string field,
                           std::string message) {
  return ApiError{400, std::move(code), std::move(message), std::move(field)};
}

inline std::string Short(std::string_view s) {
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

inline bool ObjectReader::Extras(ExtraFields* out,
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
inline bool Admissible(const ObjectReader& body,
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

}  // namespace rollwear::api::codec_internal

#endif  // ROLLWEAR_API_CODEC_READER_H_
