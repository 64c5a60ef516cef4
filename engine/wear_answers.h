// The engine's answers about the mounted rolls (engine/mounted_rolls.h):
// what GET /v1/wear, GET /v1/wear/{stand}/{position}[/profile] and
// POST /v1/forecast encode (api/codec.h). Apart from MountedRolls so that
// a file that needs only the structs (the codec, the metrics) does not
// include the store's facade.
//
// Thread-safety: plain values.
#ifndef ROLLWEAR_ENGINE_WEAR_ANSWERS_H_
#define ROLLWEAR_ENGINE_WEAR_ANSWERS_H_

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/model/profile_calibration.h"
#include "core/model/profile_interval.h"
#include "core/model/remaining_life.h"

namespace rollwear::engine {

// Predicted state of one mounted roll.
struct PositionWear {
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  std::string roll_type;
  std::string campaign_id;
  int coils = 0;
  double rolled_length_m = 0;
  double predicted_wear_um = 0;
  double interval_lo_um = 0;
  double interval_hi_um = 0;
  // The position's wear limit (MillStore::WearLimits), empty when none; the
  // remaining life until it at the campaign's mix so far
  // (core/model/remaining_life.h), empty without a limit or before the
  // roll has worn.
  std::optional<double> wear_limit_um;
  std::optional<RemainingLife> remaining;
};

// The predicted profile of one mounted roll (MountedRolls::WearProfileAt):
// its centre state, the model version and shape it was read with (shape
// empty: the default g = 1, "uncalibrated"), and per slice the profile and
// its interval.
struct ProfileWear {
  PositionWear centre;
  int64_t model_version = 0;
  std::optional<ProfileFit> shape;
  ProfilePrediction profile;
};

// Predicted wear of one mounted roll after each coil of a planned schedule
// (MountedRolls::ForecastCoils).
struct ForecastPosition {
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  std::string campaign_id;
  std::optional<double> wear_limit_um;
  std::vector<double> predicted_wear_um;               // after coil i
  std::vector<std::pair<double, double>> interval_um;  // after coil i
  int first_crossing = -1;  // first i with wear >= limit; -1 none
};

struct Forecast {
  int64_t model_version = 0;
  std::vector<std::string> coil_ids;        // the schedule's, in order
  std::vector<ForecastPosition> positions;  // by stand, top first
};

struct WearSnapshot {
  int64_t model_version = 0;
  std::vector<PositionWear> positions;  // ordered by stand, top first
};

}  // namespace rollwear::engine

#endif  // ROLLWEAR_ENGINE_WEAR_ANSWERS_H_
