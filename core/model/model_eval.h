// Coil-by-coil evaluation of a servable model (classical, classical with
// adopted terms, or the recurrent network: wear_model.h) against the
// grinder's measurements of chosen campaigns. It runs exactly the
// incremental predictor the daemon runs (predictor.h) over each measured
// roll's passes, then adds the model's measurement terms (what the grinder
// reads besides the wear, model_terms.h), so "validation gap" means the same
// thing for every kind of model the daemon may promote.
//
// Thread-safety: pure function of its arguments.
#ifndef ROLLWEAR_CORE_MODEL_MODEL_EVAL_H_
#define ROLLWEAR_CORE_MODEL_MODEL_EVAL_H_

#include <optional>
#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"
#include "core/model/metrics.h"
#include "core/model/predictor.h"
#include "core/model/reading_context.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct MeasuredPrediction {
  int campaign = -1;     // index into Dataset::campaigns
  int slot = -1;         // roll position slot (dataset.h)
  int measurement = -1;  // index into Dataset::measurements
  double measured_um = 0;
  double wear_um = 0;      // predicted centre wear
  double expected_um = 0;  // wear plus measurement terms: what the grinder
                           // is expected to read
};

// The fresh predictor state (predictor.h) of the roll of mount `mount`
// (index into Dataset::mounts) at the start of campaign `campaign`: its
// position, type, diameter, hardness and extra fields.
RollWearState MountedRollState(const WearModel& model, const Dataset& data,
                               int campaign, int mount);

// Every measured roll position of `campaigns` (indices, any order), in
// campaign then slot order.
std::vector<MeasuredPrediction> PredictMeasured(
    const WearModel& model, const Dataset& data, const DatasetIndex& index,
    const std::vector<int>& campaigns);

// Whether `model` has a measurement term (an offset on what the grinder
// reads, model_terms.h).
bool HasMeasurementTerms(const WearModel& model);

// What the grinder reads besides the wear: the sum of `model`'s measurement
// terms (model_terms.h, offset forms) for `reading`. A term counts only on
// rolls inside its scope (TermScope::CoversRoll; a measurement term is
// never scoped by grade: a reading is of a roll, not of a grade, and the
// codec and RefitWithTerms refuse it). Covariates: cooling_h (hours from
// the campaign's end), measured_at (days since 1970, covariates.h) and the
// reading's extra numeric fields; an offset_per_level term matches the
// reading's text field by its label in ModelTerm::levels, never by index
// (a record without the field reads the empty text, as an empty cell of
// measurements.csv does). A covariate without a value, or a label the fit
// never saw, adds nothing. 0 for a model without measurement terms.
double MeasurementTermsOffset(const WearModel& model, const ReadingContext& reading);

// Eq. 9 cost and average gap of `expected_um` against `measured_um`, each
// roll position slot a group of Eq. 9.
FitMetrics MetricsOfPredictions(const std::vector<MeasuredPrediction>& p);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_MODEL_EVAL_H_
