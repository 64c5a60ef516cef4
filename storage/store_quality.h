// Internal to storage: the daemon's side of "implausible is a warning, not
// a refusal" (docs/data-format.md, "Implausible values"). A measurement is
// judged by core's rules (core/dataset/data_quality.h) on the stored data
// with the new reading added, stored flagged ("<kind>: <reason>" in
// measurements.suspect), and kept out of what calibration and diagnosis fit
// (FittingDataOf).
//
// Thread-safety: pure functions of their arguments.
#ifndef ROLLWEAR_STORAGE_STORE_QUALITY_H_
#define ROLLWEAR_STORAGE_STORE_QUALITY_H_

#include <string>
#include <vector>

#include "core/dataset/data_quality.h"
#include "core/dataset/dataset.h"
#include "storage/import_plan.h"
#include "storage/store_state.h"
#include "storage/store_types.h"

namespace rollwear::storage::internal {

// Each measurement's flag, "<kind>: <reason>" or "" (parallel to the
// assessed dataset's measurements).
std::vector<std::string> SuspectFlags(const DataQuality& quality);

// The readings `in` is judged among, `in` last: those of the campaigns
// stored from the earlier of `in`'s campaign and the `window`-th newest on,
// with the per-stand exposures `c` keeps (AddExposure, store_state.h).
// Empty when `in`'s campaign is not in `c` (admitting it refuses it then).
std::vector<ReadingExposure> JudgedReadings(const Catalog& c,
                                            const MeasurementIn& in,
                                            int window);

// The flag of the last of `readings`, "<kind>: <reason>" or "" when
// plausible (or when there is none): core's JudgeLastReading. The same flag
// as AssessDataQuality gives that reading on those campaigns' stored data,
// with no read of the database.
std::string JudgeMeasurement(const std::vector<ReadingExposure>& readings);

// What the jobs fit: `all` assessed by core's rules, a flag stored with a
// measurement (`stored_flags`, parallel to its measurements) kept even when
// the rules on today's data would not raise it.
FittingData FittingDataOf(Dataset all,
                          const std::vector<std::string>& stored_flags);

// After an import of `data` under `plan` has committed: sets the flags
// (`suspect`, parallel to data.measurements) of its new measurements in
// `catalog` and returns how many new ones are flagged.
int64_t FlagImported(const Dataset& data, const ImportPlan& plan,
                     const std::vector<std::string>& suspect, Catalog* catalog);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_STORE_QUALITY_H_
