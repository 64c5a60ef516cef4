// JsonWriter: appends compact JSON text to a string, for the answer bodies
// of the hot endpoints (POST /v1/coils, GET /v1/wear), where building an
// nlohmann DOM and dumping it cost more than all the rest of the api
// layer's work on the request.
//
// The text is byte for byte what nlohmann::ordered_json::dump(-1, ' ',
// false, error_handler_t::replace) prints for the same values, so that the
// answers do not change whichever way they are built:
//   - strings: '"' and '\' escaped, \b \t \n \f \r as short escapes, other
//     bytes below 0x20 as \u00xx (lower-case hex), everything else as it
//     is, and each invalid UTF-8 sequence replaced by U+FFFD exactly where
//     nlohmann replaces it;
//   - doubles: nlohmann's own shortest-round-trip formatting (Grisu2, which
//     does not always pick the digits std::to_chars picks), integral values
//     with ".0" (1031.0), exponents from 1e15 up and below 1e-4; NaN and
//     infinities as null;
//   - integers in plain decimal.
// The caller keeps the structure valid (a Key before each member value,
// Begin/End balanced); the writer only places the commas. Member names are
// literals (JsonKey).
//
// Thread-safety: a JsonWriter belongs to one thread at a time; the free
// functions are stateless.
#ifndef ROLLWEAR_API_JSON_WRITER_H_
#define ROLLWEAR_API_JSON_WRITER_H_

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace rollwear::api {

// Appends `value` as a quoted, escaped JSON string.
void AppendJsonString(std::string_view value, std::string* out);
// Appends `value` as nlohmann prints a number_float (null when not finite).
void AppendJsonDouble(double value, std::string* out);
void AppendJsonInt(int64_t value, std::string* out);

// A member name written in the source. The compiler checks that it needs no
// escaping (printable ASCII but '"' and '\'), so JsonWriter::Key copies it
// as it is.
class JsonKey {
 public:
  template <size_t N>
  // NOLINTNEXTLINE(google-explicit-constructor): w.Key("name") reads best.
  consteval JsonKey(const char (&name)[N]) : name_(name, N - 1) {
    for (const char c : name_) {
      // A throw is not a constant expression: reached, it fails the build.
      if (c < 0x20 || c > 0x7E || c == '"' || c == '\\') {
        throw "a JSON member name here must be plain printable ASCII";
      }
    }
  }
  std::string_view name() const { return name_; }

 private:
  std::string_view name_;
};

class JsonWriter {
 public:
  // `reserve`: expected size of the text, to allocate once.
  explicit JsonWriter(size_t reserve = 256) { out_.reserve(reserve); }

  void BeginObject() { Open('{'); }
  void EndObject() { Close('}'); }
  void BeginArray() { Open('['); }
  void EndArray() { Close(']'); }

  // The name of the next member; its value follows without a comma.
  void Key(JsonKey key) {
    Separate();
    out_.push_back('"');
    out_.append(key.name());
    out_.append("\":", 2);
    need_comma_ = false;
  }

  void String(std::string_view value) {
    Separate();
    AppendJsonString(value, &out_);
    need_comma_ = true;
  }
  void Int(int64_t value) {
    Separate();
    AppendJsonInt(value, &out_);
    need_comma_ = true;
  }
  void Double(double value) {
    Separate();
    AppendJsonDouble(value, &out_);
    need_comma_ = true;
  }
  void Bool(bool value) {
    Separate();
    out_.append(value ? "true" : "false");
    need_comma_ = true;
  }
  void Null() {
    Separate();
    out_.append("null");
    need_comma_ = true;
  }
  // The number, or null when there is none.
  void OptionalDouble(const std::optional<double>& value) {
    if (value) {
      Double(*value);
    } else {
      Null();
    }
  }

  const std::string& text() const { return out_; }
  // The text; the writer is empty afterwards.
  std::string Take() {
    need_comma_ = false;
    return std::move(out_);
  }

 private:
  void Separate() {
    if (need_comma_) out_.push_back(',');
  }
  void Open(char c) {
    Separate();
    out_.push_back(c);
    need_comma_ = false;
  }
  void Close(char c) {
    out_.push_back(c);
    need_comma_ = true;
  }

  std::string out_;
  // True after a value inside an array or object: the next one needs ','.
  bool need_comma_ = false;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_JSON_WRITER_H_
