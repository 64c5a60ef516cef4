// A grinder's reading as the measurement terms see it (ReadingContext):
// the types alone, so that the store can hand a stored reading to the
// engine's predictor (storage/wear_predictor.h) without the evaluation
// code (model_eval.h) that computes its offset.
// Thread-safety: a plain value type.
#ifndef ROLLWEAR_CORE_MODEL_READING_CONTEXT_H_
#define ROLLWEAR_CORE_MODEL_READING_CONTEXT_H_

#include <optional>
#include <string>

#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"

namespace rollwear {

// A grinder's reading as the measurement terms see it: the roll it
// measures (for a term's scope) and the reading's own quantities. The batch
// path (PredictMeasured) and the daemon (storage/mill_store_history.cc)
// fill it from their records, so both read the same offset.
struct ReadingContext {
  int stand = 0;          // 1..7, the measured roll's stand
  int position = -1;      // static_cast<int>(Position)
  std::string roll_type;  // the roll's type label
  UnixSeconds measured_at = 0;
  std::optional<UnixSeconds> ended_at;  // the campaign's end (cooling_h)
  const ExtraFields* extra = nullptr;   // measurements.csv's extra fields
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_READING_CONTEXT_H_
