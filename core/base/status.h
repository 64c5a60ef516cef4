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

 private:
  Status status_;
  std::optional<T> value_;
};

}  // namespace rollwear

// Returns early from the enclosing function when `expr` is not OK.
#define ROLLWEAR_RETURN_IF_ERROR(expr)           \
  do {                                           \
    ::rollwear::Status rollwear_status_ = (expr); \
    if (!rollwear_status_.ok()) return rollwear_status_; \
  } while (0)

#endif  // ROLLWEAR_CORE_BASE_STATUS_H_
