#include "api/json_scan.h"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <utility>

#include <simdjson.h>

namespace rollwear::api {
namespace {

namespace od = simdjson::ondemand;
using simdjson::error_code;
using simdjson::SUCCESS;

// The parser and the padded copy of the body (simdjson reads up to
// SIMDJSON_PADDING bytes past the end), reused by every body of a thread.
struct ScanBuffers {
  od::parser parser;
  std::string input;
};

ScanBuffers& Buffers() {
  thread_local ScanBuffers buffers;
  return buffers;
}

ApiError BadRequest(std::string code, std::string field, std::string message) {
  return ApiError{400, std::move(code), std::move(message), std::move(field)};
}

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// RFC 8259's number grammar. simdjson refuses numbers beyond double's range
// (1e999), which are JSON all the same: they are read as strtod reads them
// (+-inf, 0) and the input rules refuse what is not finite.
bool IsJsonNumber(std::string_view s) {
  size_t i = 0;
  if (i < s.size() && s[i] == '-') ++i;
  if (i == s.size()) return false;
  if (s[i] == '0') {
    ++i;
  } else {
    if (!IsDigit(s[i])) return false;
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  auto digits = [&] {
    const size_t start = i;
    while (i < s.size() && IsDigit(s[i])) ++i;
    return i > start;
  };
  if (i < s.size() && s[i] == '.' && (++i, !digits())) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (!digits()) return false;
  }
  return i == s.size();
}

std::string_view TrimRight(std::string_view s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' ||
                        s.back() == '\n' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

// One pass over the document; every method returns simdjson's error code
// (SUCCESS or the first syntax error) and leaves the value consumed.
class Scanner {
 public:
  explicit Scanner(int max_depth) : max_depth_(max_depth) {}

  // An object of `shape`; `list`/`element` name it for a duplicate's path
  // (element -1: the body).
  error_code Object(od::object object, const ObjectShape& shape, int depth,
                    std::string_view list, int element, ScannedObject* out) {
    size_t next = 0;  // members usually come in the documented order
    for (auto member : object) {
      od::field field;
      std::string_view key;
      if (error_code e = std::move(member).get(field)) return e;
      if (error_code e = field.unescaped_key().get(key)) return e;
      const int index = IndexOf(shape, key, next);
      next = static_cast<size_t>(index + 1);
      error_code e = SUCCESS;
      if (index < 0) {
        e = Extra(field.value(), depth, key, list, element, out);
      } else if (out->members[index].kind != JsonKind::kAbsent) {
        Duplicate(list, element, key);
        e = Skip(field.value(), depth + 1);
      } else if (index == shape.list_member) {
        e = List(field.value(), shape, depth, key, &out->members[index],
                 &out->elements);
      } else {
        e = Value(field.value(), depth, &out->members[index]);
      }
      if (e) return e;
    }
    return SUCCESS;
  }

  // The first member found twice, or empty.
  const std::string& duplicate() const { return duplicate_; }

  // Validates any value at nesting `depth` (1 = a member of the body).
  error_code Skip(od::value value, int depth);

  // A literal that does not spell true, false or null is malformed.
  static error_code Literal(error_code e) {
    return e == simdjson::INCORRECT_TYPE ? simdjson::T_ATOM_ERROR : e;
  }

 private:
  // Index of `key` in shape.members (trying `hint` first), or -1.
  static int IndexOf(const ObjectShape& shape, std::string_view key,
                     size_t hint) {
    if (hint < shape.members.size() && shape.members[hint] == key) {
      return static_cast<int>(hint);
    }
    for (size_t i = 0; i < shape.members.size(); ++i) {
      if (shape.members[i] == key) return static_cast<int>(i);
    }
    return -1;
  }

  void Duplicate(std::string_view list, int element, std::string_view key) {
    if (!duplicate_.empty()) return;
    if (element >= 0) {
      duplicate_ = std::string(list) + "[" + std::to_string(element) + "].";
    }
    duplicate_ += key;
  }

  error_code Extra(od::value value, int depth, std::string_view key,
                   std::string_view list, int element, ScannedObject* out) {
    for (const auto& [name, unused] : out->extras) {
      if (name == key) {
        Duplicate(list, element, key);
        return Skip(value, depth + 1);
      }
    }
    if (out->extras.size() > kMaxExtraFields) return Skip(value, depth + 1);
    out->extras.emplace_back(key, JsonValue{});
    return Value(value, depth, &out->extras.back().second);
  }

  // The list member: up to shape.max_elements elements as objects of
  // shape.element, the others validated and counted.
  error_code List(od::value value, const ObjectShape& shape, int depth,
                  std::string_view key, JsonValue* out,
                  std::vector<ScannedObject>* elements) {
    od::json_type type;
    if (error_code e = value.type().get(type)) return e;
    if (type != od::json_type::array) return Value(value, depth, out);
    out->kind = JsonKind::kArray;
    if (depth + 1 > max_depth_) return simdjson::DEPTH_ERROR;
    od::array array;
    if (error_code e = value.get_array().get(array)) return e;
    elements->reserve(shape.max_elements);  // no moves while filling
    for (auto item : array) {
      od::value element;
      if (error_code e = std::move(item).get(element)) return e;
      const int index = static_cast<int>(out->size++);
      if (out->size > shape.max_elements) {
        if (error_code e = Skip(element, depth + 2)) return e;
        continue;
      }
      ScannedObject& scanned = elements->emplace_back();
      od::json_type element_type;
      if (error_code e = element.type().get(element_type)) return e;
      error_code e = SUCCESS;
      if (element_type == od::json_type::object) {
        od::object object;
        if (depth + 2 > max_depth_) return simdjson::DEPTH_ERROR;
        e = element.get_object().get(object);
        if (!e) {
          e = Object(object, *shape.element, depth + 2, key, index, &scanned);
        }
      } else {
        JsonValue kind_only;
        e = Value(element, depth + 1, &kind_only);
        scanned.kind = kind_only.kind;
      }
      if (e) return e;
    }
    return SUCCESS;
  }

  // A member's value at nesting `depth` (of its object): scalars kept,
  // arrays and objects validated and named.
  error_code Value(od::value value, int depth, JsonValue* out) {
    od::json_type type;
    if (error_code e = value.type().get(type)) return e;
    switch (type) {
      case od::json_type::string:
        out->kind = JsonKind::kString;
        return value.get_string().get(out->text);
      case od::json_type::number:
        out->kind = JsonKind::kNumber;
        return Number(value, out);
      case od::json_type::boolean:
        out->kind = JsonKind::kBoolean;
        return Literal(value.get_bool().get(out->boolean));
      case od::json_type::null: {
        out->kind = JsonKind::kNull;
        bool is_null = false;
        if (error_code e = Literal(value.is_null().get(is_null))) return e;
        return is_null ? SUCCESS : simdjson::N_ATOM_ERROR;
      }
      case od::json_type::array:
        out->kind = JsonKind::kArray;
        return Skip(value, depth + 1);
      case od::json_type::object:
        out->kind = JsonKind::kObject;
        return Skip(value, depth + 1);
    }
    return simdjson::TAPE_ERROR;
  }

  static error_code Number(od::value value, JsonValue* out) {
    out->text = TrimRight(value.raw_json_token());
    // A failed get_* leaves the value unconsumed, so the next one can try.
    od::number n;
    if (value.get_number().get(n) == SUCCESS) {
      switch (n.get_number_type()) {
        case od::number_type::signed_integer:
          out->integer = true;
          out->as_int = n.get_int64();
          out->number = static_cast<double>(out->as_int);
          break;
        case od::number_type::unsigned_integer:
          out->integer = out->above_int64 = true;
          out->number = static_cast<double>(n.get_uint64());
          break;
        case od::number_type::floating_point_number:
          out->number = n.get_double();
          break;
      }
      return SUCCESS;
    }
    // Integers beyond 64 bits, read as doubles.
    if (value.get_double().get(out->number) == SUCCESS) return SUCCESS;
    if (!IsJsonNumber(out->text)) return simdjson::NUMBER_ERROR;
    out->number = std::strtod(std::string(out->text).c_str(), nullptr);
    return SUCCESS;
  }

  const int max_depth_;
  std::string duplicate_;
};

error_code Scanner::Skip(od::value value, int depth) {
  od::json_type type;
  if (error_code e = value.type().get(type)) return e;
  if (type == od::json_type::object) {
    if (depth > max_depth_) return simdjson::DEPTH_ERROR;
    od::object object;
    if (error_code e = value.get_object().get(object)) return e;
    for (auto member : object) {
      od::field field;
      std::string_view key;
      if (error_code e = std::move(member).get(field)) return e;
      if (error_code e = field.unescaped_key().get(key)) return e;
      if (error_code e = Skip(field.value(), depth + 1)) return e;
    }
    return SUCCESS;
  }
  if (type == od::json_type::array) {
    if (depth > max_depth_) return simdjson::DEPTH_ERROR;
    od::array array;
    if (error_code e = value.get_array().get(array)) return e;
    for (auto item : array) {
      od::value element;
      if (error_code e = std::move(item).get(element)) return e;
      if (error_code e = Skip(element, depth + 1)) return e;
    }
    return SUCCESS;
  }
  JsonValue scalar;
  return Value(value, depth, &scalar);
}

// A root that is not an object: validated (malformed wins), then named.
error_code ScanOtherRoot(od::document& doc, od::json_type type, int max_depth) {
  switch (type) {
    case od::json_type::array: {
      od::array array;
      if (error_code e = doc.get_array().get(array)) return e;
      if (max_depth < 1) return simdjson::DEPTH_ERROR;
      Scanner scanner(max_depth);
      for (auto item : array) {
        od::value element;
        if (error_code e = std::move(item).get(element)) return e;
        if (error_code e = scanner.Skip(element, 2)) return e;
      }
      return SUCCESS;
    }
    case od::json_type::string: {
      std::string_view s;
      return doc.get_string().get(s);
    }
    case od::json_type::number: {
      double d = 0;
      std::string_view token;
      const error_code e = doc.get_double().get(d);
      if (e != simdjson::NUMBER_ERROR || doc.raw_json_token().get(token)) {
        return e;
      }
      return IsJsonNumber(TrimRight(token)) ? SUCCESS : e;
    }
    case od::json_type::boolean: {
      bool b = false;
      return Scanner::Literal(doc.get_bool().get(b));
    }
    case od::json_type::null: {
      bool is_null = false;
      if (error_code e = Scanner::Literal(doc.is_null().get(is_null))) return e;
      return is_null ? SUCCESS : simdjson::N_ATOM_ERROR;
    }
    case od::json_type::object:
      break;
  }
  return simdjson::TAPE_ERROR;
}

// "malformed JSON: <what> at line L, column C" (1-based; the position of
// the token where the parser stopped, when it knows it).
ApiError Malformed(error_code e, std::string_view body, od::document* doc) {
  std::string message = "malformed JSON: ";
  message += simdjson::error_message(e);
  const char* at = nullptr;
  if (doc != nullptr && doc->current_location().get(at) == SUCCESS) {
    const size_t offset =
        std::min(static_cast<size_t>(at - Buffers().input.data()), body.size());
    const std::string_view before = body.substr(0, offset);
    const size_t line_start = before.rfind('\n');
    const size_t column =
        line_start == std::string_view::npos ? offset + 1 : offset - line_start;
    message +=
        " at line " +
        std::to_string(std::count(before.begin(), before.end(), '\n') + 1) +
        ", column " + std::to_string(column);
  }
  return BadRequest("malformed_json", "", std::move(message));
}

// The answer to a scan's syntax error: nesting_too_deep or malformed_json.
ApiError SyntaxError(error_code e, std::string_view body, od::document* doc,
                     int max_depth) {
  if (e == simdjson::DEPTH_ERROR) {
    return BadRequest("nesting_too_deep", "",
                      "the body nests arrays/objects deeper than " +
                          std::to_string(max_depth) + " levels");
  }
  return Malformed(e, body, doc);
}

// Starts the thread's parser on a padded copy of `body`. The padding is
// written (zeros), so the parser never reads uninitialised bytes; the
// buffer keeps its capacity for the next body.
error_code Iterate(std::string_view body, od::document* doc) {
  ScanBuffers& buffers = Buffers();
  buffers.input.assign(body);
  buffers.input.append(simdjson::SIMDJSON_PADDING, '\0');
  return buffers.parser
      .iterate(buffers.input.data(), body.size(), buffers.input.size())
      .get(*doc);
}

JsonKind KindOf(od::json_type type) {
  switch (type) {
    case od::json_type::array:
      return JsonKind::kArray;
    case od::json_type::object:
      return JsonKind::kObject;
    case od::json_type::number:
      return JsonKind::kNumber;
    case od::json_type::string:
      return JsonKind::kString;
    case od::json_type::boolean:
      return JsonKind::kBoolean;
    case od::json_type::null:
      return JsonKind::kNull;
  }
  return JsonKind::kAbsent;
}

// Scans the document: its object into *out, or validates another root
// (*type says which); the first syntax error.
error_code ScanDocument(od::document& doc, const ObjectShape& shape,
                        int max_depth, ScannedObject* out, Scanner* scanner,
                        od::json_type* type) {
  if (error_code e = doc.type().get(*type)) return e;
  if (*type != od::json_type::object) {
    return ScanOtherRoot(doc, *type, max_depth);
  }
  if (max_depth < 1) return simdjson::DEPTH_ERROR;
  od::object object;
  if (error_code e = doc.get_object().get(object)) return e;
  if (error_code e = scanner->Object(object, shape, 1, "", -1, out)) return e;
  // Anything after the body's closing brace.
  const char* rest = nullptr;
  const error_code end = doc.current_location().get(rest);
  return end == simdjson::OUT_OF_BOUNDS ? SUCCESS : simdjson::TRAILING_CONTENT;
}

}  // namespace

const char* JsonKindName(JsonKind kind) {
  switch (kind) {
    case JsonKind::kAbsent:
      return "absent";
    case JsonKind::kNull:
      return "null";
    case JsonKind::kBoolean:
      return "boolean";
    case JsonKind::kNumber:
      return "number";
    case JsonKind::kString:
      return "string";
    case JsonKind::kArray:
      return "array";
    case JsonKind::kObject:
      return "object";
  }
  return "value";
}

bool ScanBody(std::string_view body, int max_depth, const ObjectShape& shape,
              ScannedObject* out, ApiError* error) {
  od::document doc;
  error_code e = Iterate(body, &doc);
  if (e) {
    *error = Malformed(e, body, nullptr);
    return false;
  }
  Scanner scanner(max_depth);
  od::json_type type = od::json_type::object;
  e = ScanDocument(doc, shape, max_depth, out, &scanner, &type);
  if (e) {
    *error = SyntaxError(e, body, &doc, max_depth);
    return false;
  }
  if (type != od::json_type::object) {
    *error = BadRequest("wrong_type", "",
                        std::string("the body must be a JSON object, got ") +
                            JsonKindName(KindOf(type)));
    return false;
  }
  if (!scanner.duplicate().empty()) {
    *error = BadRequest("invalid_value", scanner.duplicate(),
                        scanner.duplicate() + " appears twice in its object");
    return false;
  }
  return true;
}

namespace {

// The exact text of an array element (simdjson 3.0's value has no
// raw_json(): an object's or array's own, a scalar's token).
error_code RawElement(od::value& element, std::string_view* raw) {
  od::json_type type;
  if (error_code e = element.type().get(type)) return e;
  if (type == od::json_type::object) {
    od::object object;
    if (error_code e = element.get_object().get(object)) return e;
    return object.raw_json().get(*raw);
  }
  if (type == od::json_type::array) {
    od::array array;
    if (error_code e = element.get_array().get(array)) return e;
    return array.raw_json().get(*raw);
  }
  *raw = element.raw_json_token();
  return SUCCESS;
}

// The members of a list body: the array's elements' text into *elements
// (at most max_elements + 1), its member name checks into *error.
error_code ScanListMembers(od::object& object, std::string_view list,
                           int max_depth, size_t max_elements,
                           std::vector<std::string>* elements, bool* seen,
                           ApiError* error) {
  Scanner scanner(max_depth);
  for (auto member : object) {
    od::field field;
    if (error_code e = std::move(member).get(field)) return e;
    std::string_view key;
    if (error_code e = field.unescaped_key().get(key)) return e;
    od::value value = field.value();
    // The first refusal is kept; the rest of the body is still scanned, so
    // malformed JSON anywhere wins.
    auto refuse = [&](std::string code, std::string message) {
      if (error->status == 0) {
        *error = BadRequest(std::move(code), std::string(key),
                            std::move(message));
      }
      return scanner.Skip(value, 1);
    };
    if (key != list) {
      if (error_code e = refuse("unknown_field",
                                "unknown member '" + std::string(key) +
                                    "'; the body has only '" +
                                    std::string(list) + "'")) {
        return e;
      }
      continue;
    }
    if (*seen) {
      if (error_code e = refuse("invalid_value",
                                std::string(list) +
                                    " appears twice in its object")) {
        return e;
      }
      continue;
    }
    *seen = true;
    od::json_type type;
    if (error_code e = value.type().get(type)) return e;
    if (type != od::json_type::array) {
      if (error_code e = refuse("wrong_type",
                                std::string(list) + " must be an array, got " +
                                    JsonKindName(KindOf(type)))) {
        return e;
      }
      continue;
    }
    if (max_depth < 2) return simdjson::DEPTH_ERROR;
    od::array array;
    if (error_code e = value.get_array().get(array)) return e;
    for (auto item : array) {
      od::value element;
      if (error_code e = std::move(item).get(element)) return e;
      std::string_view raw;
      if (error_code e = RawElement(element, &raw)) return e;
      if (elements->size() <= max_elements) elements->emplace_back(raw);
    }
  }
  return SUCCESS;
}

}  // namespace

bool SplitListBody(std::string_view body, int max_depth, std::string_view list,
                   size_t max_elements, std::vector<std::string>* elements,
                   ApiError* error) {
  elements->clear();
  *error = ApiError{};
  od::document doc;
  error_code e = Iterate(body, &doc);
  if (e) {
    *error = SyntaxError(e, body, nullptr, max_depth);
    return false;
  }
  od::json_type type = od::json_type::object;
  e = doc.type().get(type);
  if (!e && type != od::json_type::object) {
    e = ScanOtherRoot(doc, type, max_depth);
    if (!e) {
      *error = BadRequest("wrong_type", "",
                          std::string("the body must be a JSON object, got ") +
                              JsonKindName(KindOf(type)));
      return false;
    }
  }
  bool seen = false;
  if (!e) {
    od::object object;
    e = doc.get_object().get(object);
    if (!e) {
      e = ScanListMembers(object, list, max_depth, max_elements, elements,
                          &seen, error);
    }
  }
  if (!e) {
    const char* rest = nullptr;
    const error_code end = doc.current_location().get(rest);
    if (end != simdjson::OUT_OF_BOUNDS) e = simdjson::TRAILING_CONTENT;
  }
  if (e) {
    *error = SyntaxError(e, body, &doc, max_depth);
    return false;
  }
  if (error->status != 0) return false;
  if (!seen) {
    *error = BadRequest("missing_field", std::string(list),
                        std::string(list) + " is required");
    return false;
  }
  if (elements->size() > max_elements) {
    *error = ApiError{413, "too_many_elements",
                      std::string(list) + " has more than " +
                          std::to_string(max_elements) +
                          " elements; send the schedule in parts",
                      std::string(list)};
    return false;
  }
  return true;
}

}  // namespace rollwear::api
