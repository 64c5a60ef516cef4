// `rollwear calibrate --per-roll`: K calibrated jointly with one shrunk
// wear multiplier per physical roll (core/fit/roll_effects.h), printed with
// each roll's interval; also the "identification" object every calibrate
// JSON carries (core/fit/identification.h).
//
// Thread-safety: called once from a command's Run*.
#ifndef ROLLWEAR_SERVICE_CALIBRATE_PER_ROLL_H_
#define ROLLWEAR_SERVICE_CALIBRATE_PER_ROLL_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/fit/identification.h"
#include "core/fit/roll_effects.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"

namespace rollwear::cli {

// {"identified", "sentence", "at_bound":[...], "large_error":[...],
//  "gap_ratio", "expected_ratio", "z"}
nlohmann::json IdentificationJson(const Identification& id);

// {"tau", "sigma_um", "iterations", "converged", "rolls":[{"roll_id",
//  "value", "interval":[lo,hi], "raw", "readings"}...]}
nlohmann::json RollEffectsJson(const RollEffects& e);

// The run after the data are read and split; returns the exit code (0, or
// 1 when the fit fails or is not usable).
int RunCalibratePerRoll(const CalibrateArgs& args,
                        const CalibrationOptions& options,
                        const CheckedDataset& checked,
                        const WearStatistics& stats, const CampaignSplit& split,
                        const std::vector<std::string>& original_id);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_CALIBRATE_PER_ROLL_H_
