// libFuzzer target: the JSON request decoding of every POST endpoint
// (api/codec.h): roll changes, coils, campaign ends, measurements,
// calibrations, diagnoses. Every input is given to every decoder (a valid coil
// body exercises DecodeCoil in depth and the others' error paths), at the
// daemon's default nesting limit, plus the nesting pre-scan on its own.
//
// A decoder must answer true, or false with a 400 error that has a code
// and a message; anything else (a crash, an exception escaping, a leak, a
// sanitizer report) is a bug. So is DecodeCoil's fast path accepting a body
// that its DOM path refuses or reads differently.
//
// Thread-safety: libFuzzer calls the entry point from one thread.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "api/codec.h"
#include "api/coil_fast_decode.h"

namespace {

constexpr int kMaxDepth = 16;  // ApiOptions::max_json_depth's default

void Check(bool ok, const rollwear::api::ApiError& error) {
  if (ok) return;
  if (error.status != 400 || error.code.empty() || error.message.empty()) {
    __builtin_trap();
  }
}

bool SameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(a)) == 0;
}

bool SamePass(const rollwear::storage::PassIn& a,
              const rollwear::storage::PassIn& b) {
  return a.stand == b.stand && SameBits(a.force_kn, b.force_kn) &&
         SameBits(a.width_mm, b.width_mm) && SameBits(a.length_m, b.length_m) &&
         SameBits(a.entry_thickness_mm, b.entry_thickness_mm) &&
         SameBits(a.exit_thickness_mm, b.exit_thickness_mm) &&
         SameBits(a.temperature_c, b.temperature_c) &&
         SameBits(a.speed_mps, b.speed_mps) && a.lubrication == b.lubrication &&
         SameBits(a.shift_mm, b.shift_mm);
}

// The fast path may accept only what the DOM path accepts, with the same
// result.
void CheckCoilPaths(std::string_view body) {
  using namespace rollwear;  // NOLINT(google-build-using-namespace): brevity
  storage::CoilIn fast;
  if (!api::TryDecodeCoilFast(body, kMaxDepth, &fast)) return;
  storage::CoilIn dom;
  api::ApiError error;
  if (!api::DecodeCoilDom(body, kMaxDepth, &dom, &error)) __builtin_trap();
  if (fast.coil_id != dom.coil_id || fast.campaign_id != dom.campaign_id ||
      fast.seq != dom.seq || fast.rolled_at != dom.rolled_at ||
      fast.grade != dom.grade || fast.passes.size() != dom.passes.size()) {
    __builtin_trap();
  }
  for (size_t i = 0; i < fast.passes.size(); ++i) {
    if (!SamePass(fast.passes[i], dom.passes[i])) __builtin_trap();
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
  CheckCoilPaths(body);
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
