// libFuzzer target: the JSON request decoder of every POST endpoint
// (api/codec.h on api/json_scan.h): roll changes, coils, campaign ends,
// measurements, calibrations, diagnoses, wear limits, forecasts (a list of
// coil bodies). Every input is given to every
// decoder (a valid coil body exercises DecodeCoil in depth and the others'
// error paths), at the daemon's default nesting limit.
//
// A decoder must answer true, or false with a 400 error that has a code
// and a message; anything else (a crash, an exception escaping, a leak, a
// sanitizer report) is a bug. So is a data body that decodes but whose
// record, written back as JSON (nlohmann, members in another order: extra
// fields first), decodes to anything else.
//
// Thread-safety: libFuzzer calls the entry point from one thread.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/codec.h"
#include "core/dataset/dataset_io.h"

namespace {

using namespace rollwear;  // NOLINT(google-build-using-namespace): brevity
using Json = nlohmann::ordered_json;

constexpr int kMaxDepth = 16;  // ApiOptions::max_json_depth's default
// ApiOptions::max_forecast_coils, small so that the fuzzer reaches the 413.
constexpr size_t kMaxForecastCoils = 16;

void Check(bool ok, const api::ApiError& error) {
  if (ok) return;
  if (error.status != 400 || error.code.empty() || error.message.empty()) {
    __builtin_trap();
  }
}

// An object holding `extra`'s fields (written first, so the decoder meets
// them before the known members).
Json WithExtras(const ExtraFields& extra) {
  Json j = Json::object();
  for (const auto& [name, value] : extra.factor) j[name] = value;
  for (const auto& [name, value] : extra.numeric) j[name] = value;
  return j;
}

std::string Dump(const Json& j) {
  return j.dump(-1, ' ', false, Json::error_handler_t::strict);
}

void Same(bool same) {
  if (!same) __builtin_trap();
}

void RoundTripCoil(const storage::CoilIn& in) {
  Json j = WithExtras(in.extra);
  j["coil_id"] = in.coil_id;
  j["campaign_id"] = in.campaign_id;
  j["seq"] = in.seq;
  j["rolled_at"] = FormatTimestamp(in.rolled_at);
  j["grade"] = in.grade;
  Json passes = Json::array();
  for (const storage::PassIn& p : in.passes) {
    Json q = WithExtras(p.extra);
    q["shift_mm"] = p.shift_mm;
    q["lubrication"] = p.lubrication;
    q["speed_mps"] = p.speed_mps;
    q["temperature_c"] = p.temperature_c;
    q["exit_thickness_mm"] = p.exit_thickness_mm;
    q["entry_thickness_mm"] = p.entry_thickness_mm;
    q["length_m"] = p.length_m;
    q["width_mm"] = p.width_mm;
    q["force_kn"] = p.force_kn;
    q["stand"] = StandName(p.stand);
    passes.push_back(std::move(q));
  }
  j["passes"] = std::move(passes);
  storage::CoilIn again;
  api::ApiError error;
  Same(api::DecodeCoil(Dump(j), kMaxDepth, &again, &error));
  Same(again.coil_id == in.coil_id && again.campaign_id == in.campaign_id &&
       again.seq == in.seq && again.rolled_at == in.rolled_at &&
       again.grade == in.grade && again.passes == in.passes &&
       again.extra == in.extra);
}

void RoundTripRollChange(const storage::RollChangeIn& in) {
  Json j = WithExtras(in.extra);
  j["rolls"] = Json::array();
  for (const storage::MountedRollIn& m : in.rolls) {
    Json r = WithExtras(m.extra);
    r["hardness_hb"] = m.hardness_hb;
    r["diameter_mm"] = m.diameter_mm;
    r["roll_type"] = m.roll_type;
    r["roll_id"] = m.roll_id;
    r["position"] = PositionName(m.position);
    r["stand"] = StandName(m.stand);
    j["rolls"].push_back(std::move(r));
  }
  j["started_at"] = FormatTimestamp(in.started_at);
  j["campaign_id"] = in.campaign_id;
  storage::RollChangeIn again;
  api::ApiError error;
  Same(api::DecodeRollChange(Dump(j), kMaxDepth, &again, &error));
  Same(again.campaign_id == in.campaign_id &&
       again.started_at == in.started_at && again.extra == in.extra &&
       again.rolls.size() == in.rolls.size());
  for (size_t i = 0; i < in.rolls.size(); ++i) {
    const storage::MountedRollIn& a = again.rolls[i];
    const storage::MountedRollIn& b = in.rolls[i];
    Same(a.stand == b.stand && a.position == b.position &&
         a.roll_id == b.roll_id && a.roll_type == b.roll_type &&
         a.diameter_mm == b.diameter_mm && a.hardness_hb == b.hardness_hb &&
         a.extra == b.extra);
  }
}

void RoundTripMeasurement(const storage::MeasurementIn& in) {
  Json j = WithExtras(in.extra);
  j["wear_center_um"] = in.wear_center_um;
  j["measured_at"] = FormatTimestamp(in.measured_at);
  j["roll_id"] = in.roll_id;
  j["position"] = PositionName(in.position);
  j["stand"] = StandName(in.stand);
  j["campaign_id"] = in.campaign_id;
  storage::MeasurementIn again;
  api::ApiError error;
  Same(api::DecodeMeasurement(Dump(j), kMaxDepth, &again, &error));
  Same(again.campaign_id == in.campaign_id && again.stand == in.stand &&
       again.position == in.position && again.roll_id == in.roll_id &&
       again.measured_at == in.measured_at &&
       again.wear_center_um == in.wear_center_um && again.extra == in.extra);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view body(reinterpret_cast<const char*>(data), size);
  {
    storage::RollChangeIn out;
    api::ApiError error;
    const bool ok = api::DecodeRollChange(body, kMaxDepth, &out, &error);
    Check(ok, error);
    if (ok) RoundTripRollChange(out);
  }
  {
    UnixSeconds ended_at = 0;
    api::ApiError error;
    Check(api::DecodeCampaignEnd(body, kMaxDepth, &ended_at, &error), error);
  }
  {
    storage::CoilIn out;
    api::ApiError error;
    const bool ok = api::DecodeCoil(body, kMaxDepth, &out, &error);
    Check(ok, error);
    if (ok) RoundTripCoil(out);
  }
  {
    storage::MeasurementIn out;
    api::ApiError error;
    const bool ok = api::DecodeMeasurement(body, kMaxDepth, &out, &error);
    Check(ok, error);
    if (ok) RoundTripMeasurement(out);
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
  {
    storage::WearLimitIn out;
    api::ApiError error;
    Check(api::DecodeWearLimit(body, kMaxDepth, &out, &error), error);
  }
  {
    // POST /v1/forecast: each coil as DecodeCoil reads it; beyond the coil
    // limit the answer is 413 too_many_elements.
    std::vector<storage::CoilIn> out;
    api::ApiError error;
    const bool ok =
        api::DecodeForecast(body, kMaxDepth, kMaxForecastCoils, &out, &error);
    if (!ok && error.status == 413 && error.code == "too_many_elements") {
      return 0;
    }
    Check(ok, error);
    if (ok) {
      for (const storage::CoilIn& coil : out) RoundTripCoil(coil);
    }
  }
  return 0;
}
