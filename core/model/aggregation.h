// Per-campaign sufficient statistics for calibration. For each (campaign,
// roll position) with a mounted roll, the passes of that stand are reduced
// to one load sum per strip grade:
//   S[c, p, s] = sum over passes i of grade s of Load_i
// so that the predicted centre wear is
//   d[c, p] = sum_s K(p, r(c, p), s) * S[c, p, s].
// For Wang and Nikitenko the loads carry no parameter and calibration cost
// does not grow with the number of strips. Cao's load depends on the
// exponent a, so its passes are kept (grouped by cell) as (L*lc/D, ln stress)
// pairs and summed at every evaluation.
//
// Thread-safety: immutable after Aggregate(); safe to share.
#ifndef ROLLWEAR_CORE_MODEL_AGGREGATION_H_
#define ROLLWEAR_CORE_MODEL_AGGREGATION_H_

#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/base/status.h"
#include "core/model/wear_law.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct CellLoad {
  int grade = -1;     // grade level (index into WearStatistics::grades)
  double load = 0;    // sum of BaseLoad over the cell's passes
  int pass_begin = 0;  // Cao only: range into cao_base / cao_log_stress
  int pass_end = 0;
};

// A roll mounted for a campaign at one roll-position slot: what Aggregate's
// Observation and the term fit's TermObservation (term_fit.h) start from.
struct MountedRoll {
  int campaign = -1;  // index into Dataset::campaigns
  int slot = -1;      // roll position slot (dataset.h)
  int position = -1;  // position level (index into WearStatistics::positions)
  int roll_type = -1; // roll type level
  int mount = -1;     // index into Dataset::mounts
  int measurement = -1;  // index into Dataset::measurements, -1 = unmeasured
  double measured_um = 0;  // the measurement's centre wear, 0 if unmeasured
};

// The position levels of `index`: one per slot with a mounted roll, in slot
// order (index.slots()), labelled "F6/top".
std::vector<std::string> PositionLevelNames(const DatasetIndex& index);

// Every mounted roll of `data`, campaign by campaign and slot by slot: the
// order of WearStatistics::observations and of the term fit's observations.
std::vector<MountedRoll> MountedRolls(const Dataset& data,
                                      const DatasetIndex& index);

struct Observation : MountedRoll {
  int coils = 0;
  double rolled_length_m = 0;
  std::vector<CellLoad> cells;
};

struct WearStatistics {
  WearLaw law = WearLaw::kWang;
  std::vector<std::string> positions;   // labels "F6/top", by level
  std::vector<int> position_slots;      // slot of each position level
  std::vector<std::string> roll_types;  // = Dataset::roll_types
  std::vector<std::string> grades;      // = Dataset::grades
  std::vector<Observation> observations;  // every (campaign, mounted slot)
  std::vector<double> cao_base;        // Cao: per pass L*lc/D
  std::vector<double> cao_log_stress;  // Cao: per pass ln(F/(w*lc))

  // Indices of observations that have a measurement and whose campaign is
  // in `campaigns` (a sorted or unsorted list of campaign indices).
  std::vector<int> MeasuredObservations(const std::vector<int>& campaigns) const;
  std::vector<int> MeasuredObservations() const;
};

// The load inputs of one pass on the roll of `mount`.
PassLoadInput MakeLoadInput(const Pass& pass, const Mount& mount);

StatusOr<WearStatistics> Aggregate(const Dataset& data,
                                   const DatasetIndex& index, WearLaw law);

// Predicted centre wear of one observation under `model`, whose structure
// must have been built over the statistics' levels. With `grad` non-null
// (size model.num_parameters(), zeroed by the caller) also accumulates
// d(wear)/d(log k, a).
double PredictObservation(const WearModel& model, const WearStatistics& stats,
                          const Observation& obs, double* grad = nullptr);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_AGGREGATION_H_
