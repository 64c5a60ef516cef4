// The value types of the storage layer: what MillStore's writes take
// (RollChangeIn, CoilIn, MeasurementIn), what its reads answer (MountedState,
// ModelVersion, CalibrationRecord, CampaignWearHistory, ...), and the store's
// options. Apart from the facade (storage/mill_store.h) so that a file that
// needs only the structs (the JSON codec, the repositories, the catalog)
// does not include the facade, and storage's units do not include each
// other in a loop through it.
//
// Thread-safety: plain values.
#ifndef ROLLWEAR_STORAGE_STORE_TYPES_H_
#define ROLLWEAR_STORAGE_STORE_TYPES_H_

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/data_quality.h"
#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"
#include "core/dataset/input_rules.h"
#include "core/model/ann_model.h"
#include "core/model/barrel_profile.h"
#include "core/model/model_terms.h"
#include "core/model/profile_calibration.h"
#include "core/model/roll_wear_state.h"
#include "core/model/wear_model.h"

namespace rollwear::storage {

class WearPredictor;  // wear_predictor.h

// Schema version this build writes; older files are migrated on Open, newer
// ones are refused.
constexpr int kSchemaVersion = 7;

struct StoreOptions {
  // Maximum coils committed in one group-commit transaction.
  int max_batch = 512;
  // Law and K structure of calibrations when the request names none.
  WearLaw default_law = WearLaw::kWang;
  int default_option = 1;
  // Before the first calibration (or import of a calibrated model)
  // predictions use a prior model of `default_law`/`default_option` with
  // every kF = initial_k and all other factors 1 (version 0, not stored).
  double initial_k = 0.3;
  // Wear limit of each roll position slot from the configuration, µm (0:
  // none); a limit set through SetWearLimit wins (wear_limits table).
  std::array<double, kNumRollPositionSlots> wear_limit_um{};
  // The predictions the store makes as it commits and replays
  // (wear_predictor.h); required: the engine's (engine::OpenStore).
  std::shared_ptr<const WearPredictor> predictor;
  bool IsValid(std::string* error) const;
};

struct MountedRollIn {
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  std::string roll_type;
  double diameter_mm = 0;
  double hardness_hb = 0;
  ExtraFields extra;  // the roll's extra fields: mounts.csv's extra columns
};

struct RollChangeIn {
  std::string campaign_id;
  UnixSeconds started_at = 0;
  std::vector<MountedRollIn> rolls;
  ExtraFields
      extra;  // the campaign's extra fields: campaigns.csv's extra columns
  // Set by a decoder that ran the record's input rules
  // (core/dataset/input_rules.h) on exactly these fields and found none
  // broken (api/codec_decode.cc, which names the JSON path of a broken
  // one); the store then does not run them again. Any other caller leaves
  // it false and the store checks the record.
  bool rules_checked = false;
};

// Views of `rolls` for core's RollChangeRules (valid while `rolls` lives).
std::vector<MountRecord> MountRecords(const std::vector<MountedRollIn>& rolls);

// One pass of a coil body: a coils.csv row's measured quantities.
struct PassIn : PassMeasures {
  ExtraFields extra;  // the pass's own extra fields (coils.csv's extra columns)
  bool operator==(const PassIn&) const = default;
};

struct CoilIn {
  std::string coil_id;
  std::string campaign_id;
  int seq = 0;
  UnixSeconds rolled_at = 0;
  std::string grade;
  std::vector<PassIn> passes;
  // Extra fields of the coil as a whole: extra columns of each of its
  // coils.csv rows (a name may not appear both here and in a pass).
  ExtraFields extra;
  // As RollChangeIn::rules_checked.
  bool rules_checked = false;
};

struct MeasurementIn {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  UnixSeconds measured_at = 0;
  double wear_center_um = 0;
  ExtraFields extra;  // measurements.csv's extra columns
  // Empty when plausible, else "<kind>: <reason>" (a valid number that
  // cannot be physical wear, core/dataset/data_quality.h): set by the store
  // (MillStore::AddMeasurement), stored, excluded from fitting.
  std::string suspect;
  // As RollChangeIn::rules_checked.
  bool rules_checked = false;
};

// A grinder profile across the barrel (POST /v1/profiles, profiles.csv):
// the points of one roll measured after its campaign, keyed like a
// measurement by (campaign_id, stand, position). Points keep their order;
// a repeat is equal when every field and every point is equal.
struct ProfilePointIn {
  double x_mm = 0;  // mm from the barrel centre, + towards the drive side
  double wear_um = 0;
  bool operator==(const ProfilePointIn&) const = default;
};
struct ProfileIn {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  UnixSeconds measured_at = 0;
  std::vector<ProfilePointIn> points;
  bool operator==(const ProfileIn&) const = default;
};
// Half the barrel length: a posted point farther from the centre is refused.
inline constexpr double kMaxProfileXMm = kDefaultBarrelMm / 2;

enum class WriteOutcome { kCreated, kUnchanged };

// The stored data as calibration and diagnosis see it (MillStore::
// ReadFittingData): everything, its data quality by core's rules plus the
// flags stored with measurements, and `all` without the suspects.
struct FittingData {
  Dataset all;
  Dataset fit;
  DataQuality quality;
};

// Bounds of a wear limit (µm): above 0, at most kMaxWearLimitUm.
inline constexpr double kMaxWearLimitUm = 5000;

// A wear limit as set through MillStore::SetWearLimit.
struct WearLimitIn {
  int stand = 0;
  Position position = Position::kTop;
  double limit_um = 0;
  std::string reason;  // may be empty
};

// The wear limit in force at one roll position (MillStore::WearLimits).
struct WearLimit {
  int stand = 0;
  Position position = Position::kTop;
  std::optional<double> limit_um;  // empty: no limit
  std::string source;              // "api", "config" or "" (none)
  UnixSeconds set_at = 0;          // "api" only
  std::string reason;              // "api" only
};

struct CoilOutcome {
  WriteOutcome outcome = WriteOutcome::kCreated;
  // Wear this coil added to each roll position it passed (empty passes of a
  // stand with no roll are refused, so every pass appears here).
  struct Added {
    int stand = 0;
    Position position = Position::kTop;
    std::string roll_id;
    double wear_um = 0;
    double predicted_wear_um = 0;  // roll total after this coil
  };
  std::vector<Added> added;
};

// Model name of the recurrent network in runs and model versions
// (core/model/ann_model.h).
using ::rollwear::kAnnModelName;

struct ModelVersion {
  int64_t version = 0;
  UnixSeconds created_at = 0;
  std::string model;  // law name, or kAnnModelName
  int option = 0;
  bool active = false;
  double gap_val_um = 0;  // validation gap when it was calibrated
  WearModel wear_model;
  // Activated by hand and not unpinned since (only the active version can
  // be): calibration runs and diagnosis adoptions do not replace it.
  bool pinned = false;
  // The run that made it (calibration_id 0: none recorded): its trigger
  // ("nightly", "api", "cli", "diagnosis <id>"), the source that trigger
  // stands for (ModelSource), and its figures.
  int64_t calibration_id = 0;
  std::string trigger;
  std::string source;
  double gap_train_um = 0;
  int n_train = 0, n_val = 0;
  // The profile shape the calibration run fitted on the stored grinder
  // profiles (core/fit/profile_fit.h); none without profile data (the
  // default shape g = 1). Stored in models.model_json (model_codec.h).
  std::optional<ProfileFit> profile;
};

// "nightly", "diagnosis" (trigger "diagnosis <id>") or "calibration" (any
// other trigger: api, cli): where a run's model came from.
std::string ModelSource(const std::string& trigger);

// One promotion of a model version, automatic (a calibration run or a
// diagnosis adoption) or by hand (source "manual"): a row of the audit
// trail (MillStore::ModelHistory).
struct ModelPromotion {
  int64_t id = 0;
  int64_t version = 0;
  int64_t previous_version = 0;  // 0: none before it (the prior model)
  std::string source;  // "calibration", "nightly", "diagnosis", "manual"
  std::string reason;
  UnixSeconds at = 0;
  bool pinned = false;  // a manual activation that pinned the version
};

// A finished diagnosis of the daemon, as stored (MillStore::SaveDiagnosis).
struct StoredDiagnosis {
  int64_t id = 0;
  std::string status;  // "done" or "failed"
  bool adopt = false;
  UnixSeconds queued_at = 0, started_at = 0, finished_at = 0;
  std::string verdict;  // the report's verdict ("" when failed)
  std::string message;  // why it failed, or why adoption was not recorded
  int64_t calibration_id = 0;  // the adoption's run (0: none)
  std::string report_json;     // api/diagnosis_json.h's JSON ("" when failed)
  std::string report_html;     // core's DiagnosisHtml ("" when failed)
};

// One mount of a roll (MillStore::RollLife): where and when, what it
// rolled, its predicted wear at the end of the mount (now, while the
// campaign runs) under the active model, and what the grinder measured.
struct RollMountLife {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  UnixSeconds started_at = 0;
  std::optional<UnixSeconds> ended_at;  // empty while the campaign runs
  double diameter_mm = 0;
  double hardness_hb = 0;
  int coils = 0;
  double rolled_length_m = 0;
  double predicted_wear_um = 0;
  std::optional<double> measured_um;
  // What the grinder is expected to read: the predicted wear plus the
  // model's measurement terms for that measurement (model_eval.h); set
  // with measured_um.
  std::optional<double> expected_reading_um;
  std::string measured_suspect;  // "" when plausible or not measured
};
struct RollLife {
  std::string roll_id;
  std::string roll_type;              // of its last mount
  int64_t model_version = 0;          // the model the predictions are under
  std::vector<RollMountLife> mounts;  // oldest first
  // The roll's own factor under that model's roll-effect term as served:
  // re-estimated from every plausible reading of the roll stored so far
  // (core/model/roll_factor_update.h); nullopt when the model has no such
  // term.
  std::optional<RollWearFactor> wear_factor;
};

// A roll of the inventory (MillStore::RollInventory).
struct RollSummary {
  std::string roll_id;
  std::string roll_type;        // of its last mount
  double last_diameter_mm = 0;  // at its last mount
  int campaigns = 0;
  double total_rolled_m = 0;
  std::optional<double> last_measured_um;  // most recent measurement
  std::string last_measured_suspect;
  bool mounted = false;  // in the open campaign
  int stand = 0;         // where, when mounted
  Position position = Position::kTop;
  std::string campaign_id;  // the open campaign, when mounted
};

enum class CalibrationStatus { kQueued, kRunning, kDone, kFailed };
const char* CalibrationStatusName(CalibrationStatus s);

struct CalibrationRecord {
  int64_t id = 0;
  CalibrationStatus status = CalibrationStatus::kQueued;
  std::string trigger;  // "nightly", "api", "cli"
  std::string model;    // law
  int option = 1;
  UnixSeconds queued_at = 0, started_at = 0, finished_at = 0;
  std::vector<std::pair<std::string, double>> coefficients;
  double cost = 0;
  double gap_train_um = 0;
  double gap_val_um = 0;
  double active_gap_val_um = 0;  // the active model on the same campaigns
  int n_train = 0, n_val = 0;
  bool promoted = false;
  int64_t model_version = 0;  // version created (0 if none)
  std::string message;        // failure reason or summary
};

struct StoreCounters {
  int64_t coils = 0;
  int64_t campaigns = 0;
  int64_t measurements = 0;
  // Measurements committed since the last calibration run started.
  int64_t measurements_since_last_calibration = 0;
  // Measurements stored flagged as suspect (MeasurementIn::suspect).
  int64_t suspect_measurements = 0;
  int64_t commits = 0;  // group-commit transactions
};

// What an import found, per table: rows it added and rows already stored
// with the same content (MillStore::ImportDataset).
struct ImportTableCounts {
  int64_t added = 0;
  int64_t unchanged = 0;
};
struct ImportCounts {
  ImportTableCounts campaigns, mounts, coils, measurements;
  ImportTableCounts profiles;  // one per (campaign, stand, position)
};

// Predicted wear of one roll along a campaign (MillStore::RecentWear).
struct RollWearHistory {
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  // Open campaign only: after each coil the roll rolled, the rolled length
  // so far and the predicted wear (the last point equals the engine's
  // wear answer, engine::MountedRolls::Wear).
  std::vector<double> rolled_length_m;
  std::vector<double> predicted_wear_um;
  double final_predicted_um = 0;      // under the active model
  std::optional<double> measured_um;  // grinder's centre wear, if measured
  // The measurement's suspect flag ("<kind>: <reason>"; "" when plausible
  // or not measured): shown, not fitted.
  std::string measured_suspect;
  // Measured rolls: what the grinder is expected to read, the final
  // predicted wear plus the active model's measurement terms (cooling_h, or
  // a measurement's extra field as stored with it; a term whose field the
  // measurement lacks adds 0). Equals final_predicted_um without
  // measurement terms.
  double expected_reading_um = 0;
};
struct CampaignWearHistory {
  std::string campaign_id;
  UnixSeconds started_at = 0;
  bool open = false;
  std::vector<RollWearHistory> rolls;  // by stand, top first
};

// A stored grinder profile of an ended campaign with the active model's
// prediction at each of its points (MillStore::RecentProfiles): the roll's
// replayed profile sums read with the model's shape (g = 1 when it has
// none: `calibrated` false), interpolated between slices at x_mm.
struct MeasuredProfile {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  bool calibrated = false;
  std::vector<double> x_mm;  // the grinder's points, stored order
  std::vector<double> measured_um;
  std::vector<double> predicted_um;
};

// One mounted roll of the open campaign as the writer last committed it:
// its mount and its predicted state (computed by the engine's predictor,
// wear_predictor.h).
struct MountedRoll {
  MountedRollIn mount;
  RollWearState state;
};
using RollSlots = std::array<std::optional<MountedRoll>, kNumRollPositionSlots>;

// The open campaign's mounted rolls at one moment (MillStore::Mounted),
// with the served model their states were predicted under and the wear
// limit in force at each position: what the engine answers wear queries
// and forecasts from (engine/mounted_rolls.h). `rolls` is shared with the
// store and never changed (the writer publishes a new one).
struct MountedState {
  std::shared_ptr<const ModelVersion> model;
  std::string campaign_id;  // the open campaign; empty when none
  std::shared_ptr<const RollSlots> rolls;
  std::array<std::optional<double>, kNumRollPositionSlots> wear_limit_um;
};

// A planned coil's passes as the predictor reads them, ordered by stand
// (MillStore::PlanCoils).
struct PlannedPass {
  int stand = 0;
  PassInput input;
};
struct PlannedCoil {
  std::string coil_id;
  std::vector<PlannedPass> passes;
};
// A planned schedule checked against the store, and the mounted state it
// starts from (taken in the same moment as the checks).
struct PlannedSchedule {
  MountedState start;
  std::vector<PlannedCoil> coils;
};

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_STORE_TYPES_H_
