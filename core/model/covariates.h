// The covariates a wear model can be missing: every recorded column and
// derived quantity of the data format (docs/data-format.md), plus the extra
// numeric columns and text factors a mill adds, evaluated for one pass as
// seen by the roll it wears. One catalog serves the diagnosis engine (which
// searches over it) and the predictor (which evaluates adopted terms coil by
// coil), so a term means the same thing in both.
//
// Levels:
//   pass      varies from pass to pass (force_kn, campaign_length_before_m...)
//   roll      constant for a roll in a campaign (diameter_mm, hardness_hb)
//   campaign  constant for a campaign (started_at as days since 1970-01-01,
//             extra campaign columns)
//   measurement  what happens at the grinder (cooling_h, measured_at, the
//             measurement's extra numeric and text columns): acts on the
//             measured value, not on the wear
// Calendar time: started_at (campaign) and measured_at (measurement) in days
// since `origin`, for drifts of the wear and of the gauge. A pass's rolled_at
// is not a separate covariate: it is started_at + hours_since_mount / 24,
// and as a near copy of started_at it would only split the evidence of a
// drift between two names.
// "cell" (kCellCovariateName, model_terms.h) is the constant 1: the
// covariate of cell terms, whose scope says where they act.
// roll_campaigns_before (kRollCampaignsBeforeName): how many earlier
// campaigns of the data mounted the same physical roll (roll_id), at any
// stand: a roll's service. The data format names no such quantity, so it
// is `locate_only`: the diagnosis tests and locates along it (a mismatch
// that follows a roll's service is not calendar time) but never names it
// as physics, and the predictor never serves it (NaN there).
// after_stop (kAfterStopName): a flag, 1 on the first kAfterStopCoils
// coils rolled after a stop inside the campaign (PassesAfterStop), 0
// elsewhere: a roll cooled while the mill stood and its surface rebuilt
// after the restart (its thermal crown and oxide film). The data format
// records each coil's rolled_at, not the stops, so it is `locate_only`: a
// term over hours in service that only stands in for extra wear just
// after the restarts is refused as not distinguishable from it, never
// named. It is in the catalog only when the data hold a stop and no extra
// column of the mill's is called after_stop.
// roll_id (kRollIdName): the physical roll, a factor whose levels are the
// data's roll ids in sorted order, last in the catalog. It is the
// covariate of the roll-effect form only (model_terms.h): `locate_only` for
// every other form, and the diagnosis names it only as the per-roll family
// (diagnosis_roll_family.cc); the predictor matches the mounted roll's id.
//
// Thread-safety: pure functions and immutable values.
#ifndef ROLLWEAR_CORE_MODEL_COVARIATES_H_
#define ROLLWEAR_CORE_MODEL_COVARIATES_H_

#include <limits>
#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/model/model_terms.h"

namespace rollwear {

enum class CovariateLevel { kPass, kRoll, kCampaign, kMeasurement };
enum class CovariateKind { kNumeric, kFlag, kFactor };

enum class CovariateSource {
  kForce,
  kWidth,
  kLength,
  kEntryThickness,
  kExitThickness,
  kTemperature,
  kSpeed,
  kLubrication,
  kShift,
  kSpecificForce,
  kContactLength,
  kReduction,
  kLengthBefore,
  kCoilsBefore,
  kHoursSinceMount,
  kDiameter,
  kHardness,
  kStartedAt,
  kCoolingHours,
  kMeasuredAt,
  kCell,
  kRollCampaignsBefore,
  kAfterStop,
  kRollId,
  kPassExtraNumeric,
  kMountExtraNumeric,
  kCampaignExtraNumeric,
  kMeasurementExtraNumeric,
  kPassExtraFactor,
  kMountExtraFactor,
  kCampaignExtraFactor,
  kMeasurementExtraFactor,
};

struct CovariateSpec {
  std::string name;  // canonical name, or the extra column's header
  CovariateSource source;
  CovariateLevel level;
  CovariateKind kind;
  int extra_column = -1;  // for extra columns: index in the ExtraColumns
  // True when the quantity grows monotonically within a campaign (rolled
  // length, coils, hours): candidates then include saturating and decaying
  // forms (growth vs run-in).
  bool accumulates = false;
  // Factors: the level labels (ExtraColumns::factor_levels of the column).
  std::vector<std::string> levels = {};
  // A derived quantity the data format does not name: tested and located
  // along, never named as a finding (see roll_campaigns_before above).
  bool locate_only = false;
};

// Every covariate the dataset supports, canonical ones first.
std::vector<CovariateSpec> CovariateCatalog(const Dataset& data);

// The state of a roll position before a pass, in the campaign.
struct PassContext {
  const Pass* pass = nullptr;
  int pass_row = -1;  // row in Dataset::passes (for extra columns)
  const Mount* mount = nullptr;
  int mount_row = -1;
  const Campaign* campaign = nullptr;
  int campaign_row = -1;
  int measurement_row = -1;  // -1 when not measured
  double length_before_m = 0;
  int coils_before = 0;
  // The roll's earlier campaigns in the data (RollCampaignsBefore); NaN
  // where no history is at hand (the predictor).
  double roll_campaigns_before = std::numeric_limits<double>::quiet_NaN();
  // after_stop of this pass (PassesAfterStop); NaN where the coils before
  // are not at hand (the predictor).
  double after_stop = std::numeric_limits<double>::quiet_NaN();
};

inline constexpr const char* kRollCampaignsBeforeName = "roll_campaigns_before";
inline constexpr const char* kRollIdName = "roll_id";
inline constexpr const char* kAfterStopName = "after_stop";

// A stop: a coil rolled more than kStopMinSpacingS after the coil before it
// at the same stand, and more than kStopSpacingRatio times the data's
// median spacing (a coil every 1.5-3 min is a hot strip mill's rhythm; ten
// minutes is a delay, not a gap between slabs). The flag covers the next
// kAfterStopCoils coils (the stop's first coil included): the work roll's
// surface temperature settles within minutes of rolling after an idle
// time (Stevens, Ivens & Harper 1971, J. Iron Steel Inst. 209:1, on work
// roll cooling), ten coils being about twenty minutes. Chosen from that
// physics, not fitted to any data.
inline constexpr double kStopMinSpacingS = 600;
inline constexpr double kStopSpacingRatio = 5;
inline constexpr int kAfterStopCoils = 10;

// Per row of data.passes: 1 when the pass is among the first
// kAfterStopCoils coils after a stop in its campaign (at its stand), else
// 0. A gap is measured from the latest rolled_at of the earlier coils (a
// time out of seq order makes no stop; one far in the future hides the
// stops after it), the median spacing from consecutive coils. The roll change
// that starts a campaign is not a stop here (the start of a campaign is
// campaign_coils_before's).
std::vector<unsigned char> PassesAfterStop(const Dataset& data);

// Per row of data.mounts: the number of campaigns started before this
// mount's campaign (ties: earlier row first) that mounted the same roll_id.
std::vector<int> RollCampaignsBefore(const Dataset& data);

// cooling_h: hours from the campaign's end to the grinder's measurement
// (negative when measured before the recorded end).
inline constexpr const char* kCoolingHoursName = "cooling_h";
inline double CoolingHours(UnixSeconds measured_at, UnixSeconds ended_at) {
  return static_cast<double>(measured_at - ended_at) / 3600.0;
}

// Value of a numeric or flag covariate (factor level index for factors, as
// a double). NaN when missing (e.g. cooling_h of an unmeasured campaign, an
// empty extra cell). started_at is given in days since `origin` (rollwear
// uses origin 0: days since 1970, so a term means the same in every dataset).
double CovariateValue(const CovariateSpec& spec, const Dataset& data,
                      const PassContext& ctx, UnixSeconds origin);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_COVARIATES_H_
