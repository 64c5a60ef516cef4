// MillStore: the daemon's durable state and its records, the facade (after
// Valhalla's actor) that the engine, the HTTP layer, the CLI and the tests
// call. It owns the SQLite database (WAL), the in-memory state of every
// mounted roll, and the active wear model; every write is validated against
// that state, committed, and only then acknowledged. The answers read from
// the mounted rolls (wear with interval and remaining life, profile,
// forecast) are the engine's (engine/mounted_rolls.h, on Mounted()).
//
// Durability and throughput: writes from concurrent callers are queued and
// committed by one writer thread in group commits (one transaction, one
// fsync for many coils, synchronous=FULL); a call returns only after the
// transaction that holds its write has committed. A rejected write changes
// nothing. Idempotency: a write whose key is stored returns kUnchanged when
// the content is equal and an AlreadyExists error when it differs.
//
// Errors (core/base/status.h): InvalidArgument (bad field; message names it as
// "passes[1].force_kn: must be > 0"), NotFound (unknown campaign/position/
// model/calibration), AlreadyExists (same key, other content),
// FailedPrecondition (well-formed but inconsistent: coil for an ended
// campaign, stand with no mounted roll, measurement for a roll not mounted
// there, for a campaign still running or taken before its end), Unavailable
// (database not writable: disk full, read-only), IoError (other database
// failures).
//
// Thread-safety: all methods are thread-safe.
#ifndef ROLLWEAR_STORAGE_MILL_STORE_H_
#define ROLLWEAR_STORAGE_MILL_STORE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"
#include "core/model/model_family.h"
#include "core/model/wear_model.h"
#include "storage/store_types.h"

namespace rollwear::storage {

class MillStore {
 public:
  // Opens (creating or migrating) the database at `path`.
  static StatusOr<std::unique_ptr<MillStore>> Open(const std::string& path,
                                                   const StoreOptions& options);
  virtual ~MillStore() = default;

  // Mounts rolls and opens the campaign; an open campaign still running is
  // ended at started_at.
  virtual StatusOr<WriteOutcome> ApplyRollChange(const RollChangeIn& in) = 0;
  virtual StatusOr<WriteOutcome> EndCampaign(const std::string& campaign_id,
                                             UnixSeconds ended_at) = 0;
  // Durable before it returns.
  virtual StatusOr<CoilOutcome> AddCoil(const CoilIn& in) = 0;
  // AddCoil without waiting for the commit. `done` is called exactly once
  // with what AddCoil would have returned: on the calling thread, before
  // AddCoilAsync returns, when the coil is refused; through `blocking`
  // when it repeats a committed coil (its first answer is read from the
  // database); otherwise on the store's writer thread once the coil's
  // group is durable (or has failed). `done` must be quick and must not
  // call the store's writes (it runs between two group commits).
  using CoilDone = std::function<void(StatusOr<CoilOutcome>)>;
  // Runs a task on a thread that may wait on SQLite.
  using Executor = std::function<void(std::function<void()>)>;
  virtual void AddCoilAsync(const CoilIn& in, CoilDone done,
                            const Executor& blocking) = 0;
  // A valid number that cannot be physical wear is stored flagged, not
  // refused: core's rules (core/dataset/data_quality.h) judge it on the
  // stored data plus it (in.suspect is ignored). `suspect` (may be null)
  // receives its flag, "<kind>: <reason>" or "" when plausible; for a
  // repeat, the flag stored with the first post.
  virtual StatusOr<WriteOutcome> AddMeasurement(const MeasurementIn& in,
                                                std::string* suspect) = 0;
  StatusOr<WriteOutcome> AddMeasurement(const MeasurementIn& in) {
    return AddMeasurement(in, nullptr);
  }
  // A grinder profile across the barrel (ProfileIn), all its points in one
  // transaction. Fields as CheckProfileFields (storage/validation.h:
  // "points[3].x_mm: ..."), the roll and campaign as for a measurement;
  // a repeat of a stored key is kUnchanged when every point is equal and
  // AlreadyExists otherwise.
  virtual StatusOr<WriteOutcome> AddProfile(const ProfileIn& in) = 0;

  // The open campaign's mounted rolls (none once it has ended and no roll
  // change has followed) with the served model and the wear limits in
  // force, as of the last commit: one consistent moment. The engine
  // answers the wear, profile and remaining-life queries from it
  // (engine/mounted_rolls.h).
  virtual MountedState Mounted() const = 0;

  // A planned schedule (storage/store_forecast.cc), checked as AddCoil
  // checks each coil (its field rules, a roll mounted at each stand it
  // passes), except that seq need not be new; coil_id must be new (a
  // stored one is FailedPrecondition, one planned twice InvalidArgument)
  // and every coil must be for the open campaign (FailedPrecondition).
  // Errors name the coil: "coils[3].passes[1].force_kn: must be > 0".
  // Stores nothing; answers the coils' passes as the predictor reads them
  // and the mounted state they start from, taken with the checks. The
  // engine predicts the schedule on it (engine::MountedRolls::ForecastCoils).
  virtual StatusOr<PlannedSchedule> PlanCoils(
      const std::vector<CoilIn>& coils) const = 0;

  // Wear limits (storage/store_limits.cc). SetWearLimit stores the limit of
  // one roll position durably (it wins over the configuration's,
  // StoreOptions::wear_limit_um) and returns it; InvalidArgument
  // "limit_um: ..." unless 0 < limit_um <= kMaxWearLimitUm, "stand"/
  // "position" for a position that does not exist. WearLimits answers the
  // limit in force at every roll position, by stand, top first.
  virtual StatusOr<WearLimit> SetWearLimit(const WearLimitIn& in) = 0;
  virtual std::vector<WearLimit> WearLimits() const = 0;

  // Everything stored, as a core dataset (for calibration and diagnosis).
  virtual StatusOr<Dataset> ExportDataset() const = 0;
  // The stored data as calibration and diagnosis fit it: suspects (stored
  // flags, and core's rules on the stored data) out, with their report.
  virtual StatusOr<FittingData> ReadFittingData() const = 0;
  // Loads a dataset folder's content all-or-nothing (rollwear import). With
  // `lines` (ReadDataset's, may be null) a conflict with stored content
  // names the file and line of the row; `counts` (may be null) receives per
  // table what was added and what was already stored alike. The
  // measurements core's rules flag on `data` are stored flagged.
  virtual Status ImportDataset(const Dataset& data, const DatasetLines* lines,
                               ImportCounts* counts) = 0;
  Status ImportDataset(const Dataset& data) {
    return ImportDataset(data, nullptr, nullptr);
  }

  // Models. The active version as stored (its roll-effect factors as its
  // calibration fitted them; the served ones follow the readings,
  // RollLife::wear_factor and store_roll_factors.cc).
  virtual StatusOr<ModelVersion> ActiveModel() const = 0;
  virtual std::vector<ModelVersion> ListModels() const = 0;
  // One stored version, or version 0: the prior (the configured law, option
  // and initial K, never stored; `active` while nothing was promoted), so
  // every version an answer names can be read. NotFound when unknown.
  virtual StatusOr<ModelVersion> GetModel(int64_t version) const = 0;
  // Makes a stored version active by hand, records it in the audit trail
  // with `reason` (required), re-predicts the open campaign under it, and,
  // with `pin`, pins it (calibration runs and diagnosis adoptions then
  // record their result without promoting); without, it is not pinned
  // (activating the active version with pin false unpins it). Returns the
  // version as now active. InvalidArgument "reason: ..." when the reason is
  // empty, NotFound for an unknown version.
  virtual StatusOr<ModelVersion> ActivateModel(int64_t version,
                                               const std::string& reason,
                                               bool pin) = 0;
  // The audit trail, newest first (limit <= 0: all).
  virtual StatusOr<std::vector<ModelPromotion>> ModelHistory(
      int limit) const = 0;

  // Rolls (storage/store_rolls.cc). A roll's life across campaigns, oldest
  // mount first, predicted under the active model as served (with the
  // roll's factor re-estimated from its readings); NotFound for a roll
  // never mounted.
  virtual StatusOr<RollLife> GetRollLife(const std::string& roll_id) const = 0;
  // Every roll ever mounted, by roll_id.
  virtual StatusOr<std::vector<RollSummary>> RollInventory() const = 0;

  // Finished diagnoses of the daemon (storage/store_diagnoses.cc). Save
  // stores `d` under its id (a repeat replaces it); List answers newest
  // first (limit <= 0: all) without report_json.
  virtual Status SaveDiagnosis(const StoredDiagnosis& d) = 0;
  virtual StatusOr<std::optional<StoredDiagnosis>> GetDiagnosis(
      int64_t id) const = 0;
  virtual StatusOr<std::vector<StoredDiagnosis>> ListDiagnoses(
      int limit) const = 0;
  // The largest stored diagnosis id (0: none), so ids go on after a restart.
  virtual StatusOr<int64_t> LastDiagnosisId() const = 0;

  // Calibration runs, as records: the engine (engine/calibration_runs.h)
  // fits, scores and decides; the store queues, claims and records them and
  // promotes atomically. EnqueueCalibration records a queued run of `model`
  // (a wear law and its K option, or the recurrent network, stored as
  // "ann" with option 0) and returns its id; InvalidArgument "option: ..."
  // for a law's option outside 1..3.
  virtual StatusOr<int64_t> EnqueueCalibration(const std::string& trigger,
                                               const ModelChoice& model) = 0;
  StatusOr<int64_t> EnqueueCalibration(const std::string& trigger, WearLaw law,
                                       int option) {
    return EnqueueCalibration(trigger, ModelChoice::Law(law, option));
  }
  // Claims a queued run: it is running from now, and the measurements
  // committed so far are the ones it sees ("since last calibration"
  // restarts). Returns its record; NotFound for an unknown id,
  // FailedPrecondition when it is not (or no longer) queued.
  virtual StatusOr<CalibrationRecord> ClaimCalibration(int64_t id) = 0;
  // Records a run that is already running (claimed in the same
  // transaction, so no worker picks it up): a model fitted elsewhere, such
  // as a diagnosis's adoption. Returns its record.
  virtual StatusOr<CalibrationRecord> StartProposal(const std::string& trigger,
                                                    const std::string& model,
                                                    int option) = 0;
  // Records the outcome of a claimed run (`run`'s status, figures and
  // message as given) and, with `promoted`, stores that model as a new
  // version, makes it active, writes the audit trail's row (replacing
  // `replaced_version`), all in one transaction; then re-predicts the open
  // campaign under it before any reader of runs or versions sees the
  // promotion. Fills run->model_version and run->promoted. Not promoted
  // (said in run->message) when the active version is no longer
  // `replaced_version` or is pinned: a version activated or pinned by hand
  // during the run stays. FailedPrecondition when the run is not running
  // (unknown, queued or finished), InvalidArgument when `promoted` is given
  // for a run that is not done; the database error when it could not be
  // recorded.
  virtual Status FinishCalibration(CalibrationRecord* run,
                                   std::optional<ModelVersion> promoted,
                                   int64_t replaced_version) = 0;
  virtual StatusOr<CalibrationRecord> GetCalibration(int64_t id) const = 0;
  virtual std::vector<CalibrationRecord> ListCalibrations(int limit) const = 0;

  // The open campaign (if any, with each roll's wear after every coil)
  // followed by the `ended_campaigns` most recently started ended campaigns
  // that have a measurement, newest first, all replayed under the active
  // model (storage/mill_store_history.cc).
  virtual StatusOr<std::vector<CampaignWearHistory>> RecentWear(
      int ended_campaigns) const = 0;
  // The grinder profiles of the `ended_campaigns` most recently started
  // ended campaigns that have one, newest first (by stand, top first in a
  // campaign), each with the active model's prediction at its points
  // (storage/mill_store_profile_read.cc).
  virtual StatusOr<std::vector<MeasuredProfile>> RecentProfiles(
      int ended_campaigns) const = 0;

  virtual StoreCounters Counters() const = 0;
  // True when the database answers a trivial query.
  virtual bool Healthy() const = 0;
};

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_MILL_STORE_H_
