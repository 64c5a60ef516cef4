// Status and StatusOr: the one error model of rollwear's core and storage
// layers (after leveldb::Status / absl::StatusOr). A Status is either OK or
// carries a code and a human-readable message; the message of a data error
// names file:line:column and the rule that was broken. HTTP codes are chosen
// from the Status code in the api layer only.
//
// Thread-safety: immutable value types; safe to share after construction.
#ifndef ROLLWEAR_CORE_BASE_STATUS_H_
#define ROLLWEAR_CORE_BASE_STATUS_H_

#include <cassert>
#include <optional>
#include <string>
#include <utility>

namespace rollwear {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,     // malformed or out-of-range input
  kNotFound,            // unknown campaign, position, model...
  kAlreadyExists,       // duplicate key with different content
  kFailedPrecondition,  // well-formed but inconsistent with stored state
  kNumericalFailure,    // solver diverged / result unusable
  kIoError,             // file or database failure
  kUnavailable,         // resource temporarily unavailable (disk full...)
  kInternal,
};

const char* StatusCodeName(StatusCode code);

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message)
      : code_(code), message_(std::move(message)) {}

  static Status Ok() { return Status(); }
  static Status InvalidArgument(std::string m) {
    return {StatusCode::kInvalidArgument, std::move(m)};
  }
  static Status NotFound(std::string m) {
    return {StatusCode::kNotFound, std::move(m)};
  }
  static Status AlreadyExists(std::string m) {
    return {StatusCode::kAlreadyExists, std::move(m)};
  }
  static Status FailedPrecondition(std::string m) {
    return {StatusCode::kFailedPrecondition, std::move(m)};
  }
  static Status NumericalFailure(std::string m) {
    return {StatusCode::kNumericalFailure, std::move(m)};
  }
  static Status IoError(std::string m) {
    return {StatusCode::kIoError, std::move(m)};
  }
  static Status Unavailable(std::string m) {
    return {StatusCode::kUnavailable, std::move(m)};
  }
  static Status Internal(std::string m) {
    return {StatusCode::kInternal, std::move(m)};
  }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "invalid_argument: coils.csv:12:5 force_kn: must be > 0".
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

// A value or the Status explaining why there is none.
template <typename T>
class StatusOr {
 public:
  StatusOr(Status status) : status_(std::move(status)) {  // NOLINT
    assert(!status_.ok());
  }
  StatusOr(T value) : value_(std::move(value)) {}  // NOLINT

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }
  T& operator*() & { return *value_; }
  const T& operator*() const& { return *value_; }
  // `*std::move(s)` moves the value out (without this overload it bound to
  // the const& one above and copied: a whole Dataset in ReadCheckedDataset).
  T&& operator*() && { return std::move(*value_); }

 private:
  Status status_;
  std::optional<T> value_;
};

}  // namespace rollwear

// Early-return helpers (after Abseil's RETURN_IF_ERROR / ASSIGN_OR_RETURN
// and Arrow's ARROW_ASSIGN_OR_RAISE). Usable in any function that returns
// Status or StatusOr<U>; the Status is returned unchanged (same code, same
// message).
//
//   ROLLWEAR_RETURN_IF_ERROR(WriteHeader(out));
//   ROLLWEAR_ASSIGN_OR_RETURN(WearStatistics stats, BuildStatistics(ds));
//   ROLLWEAR_ASSIGN_OR_RETURN(existing_value, Parse(text));  // assigns
//
// ROLLWEAR_RETURN_IF_ERROR(expr): `expr` yields a Status; returns it when it
// is not OK.
// ROLLWEAR_ASSIGN_OR_RETURN(lhs, expr): `expr` yields a StatusOr<T>; returns
// its Status when it is not OK, otherwise moves the value into `lhs` (a
// declaration or an existing variable; move-only T is fine). `lhs` may not
// contain an unparenthesised comma (`expr` may). It expands to several
// statements, so it cannot be the lone body of an unbraced if/else/for.
// Each expansion names its temporary after __COUNTER__, so several uses in
// one scope, or an `expr` naming another temporary, do not collide.
#define ROLLWEAR_STATUS_CONCAT_INNER_(a, b) a##b
#define ROLLWEAR_STATUS_CONCAT_(a, b) ROLLWEAR_STATUS_CONCAT_INNER_(a, b)

#define ROLLWEAR_RETURN_IF_ERROR(...) \
  ROLLWEAR_RETURN_IF_ERROR_IMPL_(     \
      ROLLWEAR_STATUS_CONCAT_(rollwear_status_, __COUNTER__), __VA_ARGS__)
#define ROLLWEAR_RETURN_IF_ERROR_IMPL_(tmp, ...) \
  do {                                           \
    ::rollwear::Status tmp = (__VA_ARGS__);      \
    if (!tmp.ok()) return tmp;                   \
  } while (0)

#define ROLLWEAR_ASSIGN_OR_RETURN(lhs, ...)                          \
  ROLLWEAR_ASSIGN_OR_RETURN_IMPL_(                                   \
      ROLLWEAR_STATUS_CONCAT_(rollwear_statusor_, __COUNTER__), lhs, \
      __VA_ARGS__)
#define ROLLWEAR_ASSIGN_OR_RETURN_IMPL_(tmp, lhs, ...) \
  auto tmp = (__VA_ARGS__);                            \
  if (!tmp.ok()) return tmp.status();                  \
  lhs = std::move(tmp).value()

#endif  // ROLLWEAR_CORE_BASE_STATUS_H_
