// `--predictions FILE` of calibrate (also with --terms) and ann: one CSV
// row per measured reading used, the common footing on which any model
// (rollwear's, the study's, the study authors' network) is scored on the
// same readings (../shared/api.md):
//   campaign_id,stand,position,roll_id,set,measured_um,predicted_um,lo_um,hi_um
// lo_um/hi_um: the 95 % prediction interval (empty when the model has
// none); set: train or validation. A campaign split in two by a split file
// (core/model/given_split.h) is written under its original id.
//
// Thread-safety: called once from a command's Run*.
#ifndef ROLLWEAR_SERVICE_PREDICTIONS_CSV_H_
#define ROLLWEAR_SERVICE_PREDICTIONS_CSV_H_

#include <functional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/aggregation.h"
#include "core/model/metrics.h"
#include "core/model/model_eval.h"
#include "core/model/wear_model.h"

namespace rollwear::cli {

struct PredictionRow {
  std::string campaign_id, roll_id;
  int stand = 0;
  Position position = Position::kTop;
  bool train = true;
  double measured_um = 0, predicted_um = 0;
  double lo_um = 0, hi_um = 0;  // NaN: no interval
};

// The prediction and the sd of a new reading of observation o.
using ObservationPredictor =
    std::function<void(int o, double* predicted_um, double* sd_um)>;

// The rows of the measured observations of split's training then
// validation campaigns. `original_id` (may be empty) maps a campaign index
// to the id written.
std::vector<PredictionRow> PredictionRows(
    const Dataset& data, const WearStatistics& stats,
    const CampaignSplit& split, const std::vector<std::string>& original_id,
    const ObservationPredictor& predict);

// A law's own predictor: PredictObservation and its noise model
// (sd^2 = noise_sd_um^2 + (noise_rel * wear)^2, wear_model.h).
ObservationPredictor LawPredictor(const WearModel& model,
                                  const WearStatistics& stats);

// The rows of a model evaluated coil by coil (core/model/model_eval.h: a
// model with terms), all in one set; the interval from the model's noise
// model about what the grinder is expected to read.
std::vector<PredictionRow> MeasuredPredictionRows(
    const Dataset& data, const WearModel& model,
    const std::vector<MeasuredPrediction>& predictions, bool train,
    const std::vector<std::string>& original_id);

Status WritePredictionsCsv(const std::string& file,
                           const std::vector<PredictionRow>& rows);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_PREDICTIONS_CSV_H_
