// Internal to the api layer (api/codec_decode.cc): reads one JSON request
// body with simdjson's On-Demand parser (Debian libsimdjson-dev) against the
// shape the body should have. One pass over the document visits every value
// (known members, extra members, elements, values nested in a member of the
// wrong type), so the whole body is validated as JSON - grammar, string
// escapes, UTF-8, trailing content - before the caller checks a single field:
// a malformed body is malformed_json whatever else is wrong with it, as with
// a DOM. The result holds each known member's value by index in the shape,
// the other ("extra") members in body order, and the elements of the shape's
// list member (a coil's passes, a roll change's rolls) as objects of their
// own shape. simdjson itself is included by json_scan.cc only.
//
// Thread-safety: ScanBody uses a thread_local parser and input buffer; the
// string views of a ScannedObject point into them and stay valid until the
// next ScanBody on the same thread.
#ifndef ROLLWEAR_API_JSON_SCAN_H_
#define ROLLWEAR_API_JSON_SCAN_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/codec.h"

namespace rollwear::api {

enum class JsonKind : uint8_t {
  kAbsent,  // a known member the body does not have
  kNull,
  kBoolean,
  kNumber,
  kString,
  kArray,
  kObject,
};

// "null", "boolean", "number", "string", "array", "object" (the words of
// the error messages).
const char* JsonKindName(JsonKind kind);

// One member's value. Arrays and objects are validated, not kept (except
// the shape's list member, see ScannedObject::elements).
struct JsonValue {
  JsonKind kind = JsonKind::kAbsent;
  bool boolean = false;
  // A number token without fraction or exponent that fits in 64 bits:
  // `integer`, with `as_int` its value, or `above_int64` for one in
  // (INT64_MAX, UINT64_MAX].
  bool integer = false;
  bool above_int64 = false;
  int64_t as_int = 0;
  // A number's value (an integer converted exactly as strtod would round
  // its digits; +-inf or 0 beyond double's range, as strtod gives).
  double number = 0;
  // A string's decoded value; a number's token as sent.
  std::string_view text;
  // An array's number of elements (the list member's only).
  size_t size = 0;
};

// The members a body object may have.
inline constexpr size_t kMaxShapeMembers = 10;
struct ObjectShape {
  std::span<const std::string_view> members;  // at most kMaxShapeMembers
  // Index in `members` of the array whose elements are objects of shape
  // `element`; -1: none. At most `max_elements` elements are kept.
  int list_member = -1;
  const ObjectShape* element = nullptr;
  size_t max_elements = 0;
};

using ExtraMember = std::pair<std::string_view, JsonValue>;

struct ScannedObject {
  // This value's JSON type (an element of a list may be anything).
  JsonKind kind = JsonKind::kObject;
  // Known members by index in the shape (kAbsent when not sent).
  std::array<JsonValue, kMaxShapeMembers> members;
  // Every other member, in body order; at most kMaxExtraFields + 1 are
  // kept (the decoder refuses more than kMaxExtraFields).
  std::vector<ExtraMember> extras;
  // The list member's first max_elements elements (its size is in
  // members[list_member].size).
  std::vector<ScannedObject> elements;
};

// Scans `body` as an object of `shape`. False and *error (400), the first
// of: nesting_too_deep (an array or object deeper than max_depth levels,
// the body being level 1) or malformed_json (message with line and column
// where the parser knows them), whichever the scan meets first; wrong_type
// (the body is not an object); invalid_value (a member twice in one object,
// field = its path).
bool ScanBody(std::string_view body, int max_depth, const ObjectShape& shape,
              ScannedObject* out, ApiError* error);

// Scans `body` as an object whose one member `list` is an array (of any
// values) and copies the exact JSON text of each element into *elements,
// to be decoded on its own (POST /v1/forecast's coils with DecodeCoil).
// False and *error (400): nesting_too_deep, malformed_json, wrong_type (the
// body is not an object, `list` is not an array), missing_field (no
// `list`), unknown_field (another member), invalid_value (`list` twice);
// more than max_elements elements: 413 too_many_elements.
bool SplitListBody(std::string_view body, int max_depth, std::string_view list,
                   size_t max_elements, std::vector<std::string>* elements,
                   ApiError* error);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_JSON_SCAN_H_
