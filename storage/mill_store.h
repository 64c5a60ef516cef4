// MillStore: the daemon's durable state and the one facade (after Valhalla's
// actor) that the HTTP layer, the CLI and the tests call. It owns the SQLite
// database (WAL), the in-memory state of every mounted roll, and the active
// wear model; every write is validated against that state, committed, and
// only then acknowledged.
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
// there), Unavailable (database not writable: disk full, read-only),
// IoError (other database failures).
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

#include "core/dataset/dataset.h"
#include "core/base/status.h"
#include "core/model/wear_model.h"

namespace rollwear::storage {

// Schema version this build writes; older files are migrated on Open, newer
// ones are refused.
constexpr int kSchemaVersion = 3;

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
  // Seed of the 2/3-1/3 campaign split used by calibration runs.
  uint64_t split_seed = 1;
  bool IsValid(std::string* error) const;
};

struct MountedRollIn {
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  std::string roll_type;
  double diameter_mm = 0;
  double hardness_hb = 0;
};

struct RollChangeIn {
  std::string campaign_id;
  UnixSeconds started_at = 0;
  std::vector<MountedRollIn> rolls;
};

// One pass of a coil body: a coils.csv row's measured quantities.
using PassIn = PassMeasures;

struct CoilIn {
  std::string coil_id;
  std::string campaign_id;
  int seq = 0;
  UnixSeconds rolled_at = 0;
  std::string grade;
  std::vector<PassIn> passes;
};

struct MeasurementIn {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  UnixSeconds measured_at = 0;
  double wear_center_um = 0;
};

enum class WriteOutcome { kCreated, kUnchanged };

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

struct WearSnapshot {
  int64_t model_version = 0;
  std::vector<PositionWear> positions;  // ordered by stand, top first
};

// Model name of the recurrent network in runs and model versions.
inline constexpr char kAnnModelName[] = "ann";

struct ModelVersion {
  int64_t version = 0;
  UnixSeconds created_at = 0;
  std::string model;  // law name, or kAnnModelName
  int option = 0;
  bool active = false;
  double gap_val_um = 0;  // validation gap when it was calibrated
  WearModel wear_model;
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
  int64_t commits = 0;  // group-commit transactions
};

// Predicted wear of one roll along a campaign (MillStore::RecentWear).
struct RollWearHistory {
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  // Open campaign only: after each coil the roll rolled, the rolled length
  // so far and the predicted wear (the last point equals Wear()'s).
  std::vector<double> rolled_length_m;
  std::vector<double> predicted_wear_um;
  double final_predicted_um = 0;      // under the active model
  std::optional<double> measured_um;  // grinder's centre wear, if measured
  // Measured rolls: what the grinder is expected to read, the final
  // predicted wear plus the active model's measurement terms (cooling_h;
  // a term on a measurement's extra column adds 0 here, the API carries no
  // extra columns). Equals final_predicted_um without measurement terms.
  double expected_reading_um = 0;
};
struct CampaignWearHistory {
  std::string campaign_id;
  UnixSeconds started_at = 0;
  bool open = false;
  std::vector<RollWearHistory> rolls;  // by stand, top first
};

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
  virtual StatusOr<WriteOutcome> AddMeasurement(const MeasurementIn& in) = 0;

  // The rolls of the open campaign (none once it has ended and no roll
  // change has followed).
  virtual WearSnapshot Wear() const = 0;
  virtual StatusOr<PositionWear> WearAt(int stand, Position position) const = 0;

  // Everything stored, as a core dataset (for calibration and diagnosis).
  virtual StatusOr<Dataset> ExportDataset() const = 0;
  // Loads a dataset folder's content all-or-nothing (rollwear import).
  virtual Status ImportDataset(const Dataset& data) = 0;

  // Models.
  virtual StatusOr<ModelVersion> ActiveModel() const = 0;
  virtual std::vector<ModelVersion> ListModels() const = 0;

  // Calibration runs: Enqueue records a queued run and returns its id;
  // RunCalibration executes a queued run (called by the job worker):
  // calibrates on the stored data with the seeded 2/3-1/3 split, compares
  // with the active model on the same validation campaigns, promotes
  // atomically when no worse, and re-predicts open campaigns.
  // RunCalibration returns OK once the run is recorded, done or failed
  // (see GetCalibration); NotFound for an unknown id, FailedPrecondition
  // when the run is not queued, the database error when it could not be
  // recorded. The List* calls answer newest first (limit <= 0: all).
  virtual StatusOr<int64_t> EnqueueCalibration(const std::string& trigger,
                                               WearLaw law, int option) = 0;
  virtual Status RunCalibration(int64_t id) = 0;
  // Queues a training run of the recurrent network (model "ann",
  // core/ann/ann_study.h); RunCalibration runs it like any other run.
  virtual StatusOr<int64_t> EnqueueAnnTraining(const std::string& trigger) = 0;
  // Records and runs at once a run for a model fitted elsewhere (a
  // diagnosis's adopted model: option 1 plus terms) on `data`, the data it
  // was fitted on: it and the active model are scored coil by coil on the
  // validation campaigns of `data` under `split_seed` (the campaigns the
  // candidate was not fitted on), and it is promoted when no worse. Runs
  // one at a time with RunCalibration. Returns the run's record (done or
  // failed); an error only when the run could not be recorded.
  virtual StatusOr<CalibrationRecord> ProposeModel(
      const std::string& trigger, const std::string& model, int option,
      const WearModel& candidate, const Dataset& data, uint64_t split_seed) = 0;
  virtual StatusOr<CalibrationRecord> GetCalibration(int64_t id) const = 0;
  virtual std::vector<CalibrationRecord> ListCalibrations(int limit) const = 0;

  // The open campaign (if any, with each roll's wear after every coil)
  // followed by the `ended_campaigns` most recently started ended campaigns
  // that have a measurement, newest first, all replayed under the active
  // model (storage/mill_store_history.cc).
  virtual StatusOr<std::vector<CampaignWearHistory>> RecentWear(
      int ended_campaigns) const = 0;

  virtual StoreCounters Counters() const = 0;
  // True when the database answers a trivial query.
  virtual bool Healthy() const = 0;
};

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_MILL_STORE_H_
