// libFuzzer target: the JSON request decoding of every POST endpoint
// (api/codec.h): roll changes, coils, campaign ends, measurements,
// calibrations, diagnoses. Every input is given to every decoder (a valid coil
// body exercises DecodeCoil in depth and the others' error paths), at the
// daemon's default nesting limit, plus the nesting pre-scan on its own.
//
// A decoder must answer true, or false with a 400 error that has a code
// and a message; anything else (a crash, an exception escaping, a leak, a
// sanitizer report) is a bug.
//
// Thread-safety: libFuzzer calls the entry point from one thread.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "api/codec.h"

namespace {

constexpr int kMaxDepth = 16;  // ApiOptions::max_json_depth's default

void Check(bool ok, const rollwear::api::ApiError& error) {
  if (ok) return;
  if (error.status != 400 || error.code.empty() || error.message.empty()) {
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rollwear;  // NOLINT(google-build-using-namespace): brevity
  const std::string_view body(reinterpret_cast<const char*>(data), size);
  {
    storage::RollChangeIn out;
    api::ApiError error;
    Check(api::DecodeRollChange(body, kMaxDepth, &out, &error), error);
  }
  {
    UnixSeconds ended_at = 0;
    api::ApiError error;
    Check(api::DecodeCampaignEnd(body, kMaxDepth, &ended_at, &error), error);
  }
  {
    storage::CoilIn out;
    api::ApiError error;
    Check(api::DecodeCoil(body, kMaxDepth, &out, &error), error);
  }
  {
    storage::MeasurementIn out;
    api::ApiError error;
    Check(api::DecodeMeasurement(body, kMaxDepth, &out, &error), error);
  }
  {
    api::CalibrationRequest out;
    api::ApiError error;
    Check(api::DecodeCalibrationRequest(body, kMaxDepth, &out, &error), error);
  }
  {
    api::DiagnosisRequest out;
    api::ApiError error;
    Check(api::DecodeDiagnosisRequest(body, kMaxDepth, &out, &error), error);
  }
  if (api::JsonNestingDepth(body, 1000) < 0) __builtin_trap();
  return 0;
}
