// Internal to storage: the MillStore implementation (declared here, defined
// in mill_store_impl.cc (opening, admission, reads), mill_store_writer.cc (the
// group-commit writer and publishing), mill_store_calibration.cc (models and
// the records of calibration runs), store_roll_factors.cc (the served
// model's per-roll factors) and the other store_*.cc files).
//
// State and locks:
//   mu_ guards the catalogs, the queue, the live roll states, the active
//       model pointers (as stored and as served) and the counters,
//       committed_coil_ids_, and lookup_db_ (used to read a stored coil while
//       admitting a write). Held only briefly, never across a commit.
//   committed_  the catalog of what the database holds (published state);
//   committed_coil_ids_  hashes of every committed coil id: a coil id it
//               does not contain is not stored, so admitting a new coil
//               reads nothing from SQLite (filled by Init, extended by
//               PublishBatch in the same critical section that drops the
//               coil from spec_.pending_coils);
//   spec_       committed_ plus every write queued or being committed, which
//               is what a new write is validated against;
//   rolls_      the open campaign's roll states, replaced after each commit.
//   read_mu_ guards read_db_, the connection of the small read queries.
//   publish_mu_ makes a model change visible at once: the writer holds it
//       from the commit of a task that installs a model (promotion,
//       activation) until the model is installed, and the reads of
//       calibration runs, model versions and the audit trail hold it too,
//       so that nobody reads "done, promoted to version v" while
//       GET /v1/models/active still answers the old version. Taken before
//       read_mu_ or mu_, never while holding either. A plain mutex, not a
//       shared one: those reads are serialised by read_mu_ anyway, and
//       glibc's rwlock prefers readers, so clients polling the runs could
//       keep the writer (and every coil behind it) waiting.
//   promote_mu_ serialises hand activations and recorded promotions
//       (ActivateModel, FinishCalibration); held across their RunTask, and
//       taken before publish_mu_, read_mu_ or mu_, never while holding one.
//   writer_db_ is used by the writer thread only (and by Init before it
//   starts).
//
// Thread-safety: all public methods are thread-safe.
#ifndef ROLLWEAR_STORAGE_MILL_STORE_IMPL_H_
#define ROLLWEAR_STORAGE_MILL_STORE_IMPL_H_

#include <array>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/dataset/timestamp.h"
#include "core/model/roll_wear_state.h"
#include "storage/coil_id_filter.h"
#include "storage/import_plan.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "storage/store_state.h"
#include "storage/wear_predictor.h"

namespace rollwear::storage::internal {

enum class WriteKind {
  kRollChange,
  kEndCampaign,
  kCoil,
  kMeasurement,
  kImport,  // runs alone in its transaction
  kTask,    // calibration bookkeeping; runs alone in its transaction
};

// An import or a task: runs alone in its transaction.
inline bool IsExclusive(WriteKind k) {
  return k == WriteKind::kImport || k == WriteKind::kTask;
}

// A roll change or a campaign end: the writes that follow it wait for its
// answer (coils go to the campaign a roll change opens), so none can come
// while the writer lingers.
inline bool IsBarrier(WriteKind k) {
  return k == WriteKind::kRollChange || k == WriteKind::kEndCampaign;
}

// A queued write of this kind ends the writer's linger: it commits alone
// or nothing can follow it before its answer.
inline bool EndsLinger(WriteKind k) { return IsExclusive(k) || IsBarrier(k); }

// One queued write and, once `done` is ready, its result.
struct WriteItem {
  WriteKind kind = WriteKind::kTask;
  // An idempotent repeat of a write that is still queued: nothing to write,
  // acknowledged with the batch (so never before its twin is durable).
  bool unchanged = false;

  RollChangeIn roll_change;                  // kRollChange
  std::string campaign_id;                   // kEndCampaign
  UnixSeconds ended_at = 0;                  // kEndCampaign
  CoilIn coil_in;                            // kCoil, as posted
  StoredCoil coil;                           // kCoil, canonical
  std::string coil_wear;                     // kCoil, EncodeCoilWear(answer)
  MeasurementIn measurement;                 // kMeasurement
  const Dataset* dataset = nullptr;          // kImport (owned by the caller)
  const DatasetLines* lines = nullptr;       // kImport (caller's; may be null)
  std::vector<StoredCoil> dataset_coils;     // kImport
  std::vector<std::string> dataset_suspect;  // kImport, SuspectFlags
  ImportPlan plan;                           // kImport
  std::function<Status(Db*)> task;           // kTask: inside the transaction
  std::function<void(Db*)> after_commit;     // kTask: writer thread, after

  Status status;
  CoilOutcome coil_outcome;
  // Set for AddCoilAsync: called by the writer instead of `done`.
  std::function<void()> on_done;
  std::promise<void> done;
};

// What predictions depend on: the model and the open campaign's rolls. The
// writer computes the state a batch leaves on a copy before committing it
// (so each coil's answer is stored with the coil) and installs the copy
// after the commit.
struct LiveState {
  std::shared_ptr<const ModelVersion> model;
  // The prior was rebuilt for new positions (PredictBatch): `model` is
  // then the stored version too.
  bool prior_rebuilt = false;
  RollSlots rolls;
  std::string open_campaign;
  uint32_t positions_seen = 0;
};

class MillStoreImpl final : public MillStore {
 public:
  explicit MillStoreImpl(const StoreOptions& options) : options_(options) {}
  ~MillStoreImpl() override;

  // Opens and migrates the database, loads the state, starts the writer.
  Status Init(const std::string& path);

  StatusOr<WriteOutcome> ApplyRollChange(const RollChangeIn& in) override;
  StatusOr<WriteOutcome> EndCampaign(const std::string& campaign_id,
                                     UnixSeconds ended_at) override;
  StatusOr<CoilOutcome> AddCoil(const CoilIn& in) override;
  void AddCoilAsync(const CoilIn& in, CoilDone done,
                    const Executor& blocking) override;
  using MillStore::AddMeasurement;
  StatusOr<WriteOutcome> AddMeasurement(const MeasurementIn& in,
                                        std::string* suspect) override;

  StatusOr<WriteOutcome> AddProfile(
      const ProfileIn& in) override;  // store_profiles.cc

  MountedState Mounted() const override;
  StatusOr<PlannedSchedule> PlanCoils(
      const std::vector<CoilIn>& coils) const override;  // store_forecast.cc
  StatusOr<WearLimit> SetWearLimit(const WearLimitIn& in) override;
  std::vector<WearLimit> WearLimits() const override;  // store_limits.cc

  StatusOr<Dataset> ExportDataset() const override;
  // A new reading is judged among the readings of this many most recent
  // campaigns (JudgeMeasurement, store_quality.h).
  static constexpr int kJudgedCampaigns = 50;
  StatusOr<FittingData> ReadFittingData() const override;
  using MillStore::ImportDataset;
  Status ImportDataset(const Dataset& data, const DatasetLines* lines,
                       ImportCounts* counts) override;

  StatusOr<ModelVersion> ActiveModel() const override;
  std::vector<ModelVersion> ListModels() const override;
  // ---- store_models_audit.cc
  StatusOr<ModelVersion> GetModel(int64_t version) const override;
  StatusOr<ModelVersion> ActivateModel(int64_t version,
                                       const std::string& reason,
                                       bool pin) override;
  StatusOr<std::vector<ModelPromotion>> ModelHistory(int limit) const override;
  // ---- store_rolls.cc
  StatusOr<RollLife> GetRollLife(const std::string& roll_id) const override;
  StatusOr<std::vector<RollSummary>> RollInventory() const override;
  // ---- store_diagnoses.cc
  Status SaveDiagnosis(const StoredDiagnosis& d) override;
  StatusOr<std::optional<StoredDiagnosis>> GetDiagnosis(
      int64_t id) const override;
  StatusOr<std::vector<StoredDiagnosis>> ListDiagnoses(
      int limit) const override;
  StatusOr<int64_t> LastDiagnosisId() const override;

  using MillStore::EnqueueCalibration;
  StatusOr<int64_t> EnqueueCalibration(const std::string& trigger,
                                       const ModelChoice& model) override;
  StatusOr<CalibrationRecord> ClaimCalibration(int64_t id) override;
  StatusOr<CalibrationRecord> StartProposal(const std::string& trigger,
                                            const std::string& model,
                                            int option) override;
  Status FinishCalibration(CalibrationRecord* run,
                           std::optional<ModelVersion> promoted,
                           int64_t replaced_version) override;
  StatusOr<CalibrationRecord> GetCalibration(int64_t id) const override;
  std::vector<CalibrationRecord> ListCalibrations(int limit) const override;

  StatusOr<std::vector<CampaignWearHistory>> RecentWear(
      int ended_campaigns) const override;  // mill_store_history.cc
  StatusOr<std::vector<MeasuredProfile>> RecentProfiles(
      int ended_campaigns) const override;  // mill_store_profile_read.cc
  StoreCounters Counters() const override;
  bool Healthy() const override;

 private:
  // The flag stored (or queued) with the measurement of `in`'s key, or
  // nullopt when that key has no measurement yet.
  std::optional<std::string> StoredSuspect(const MeasurementIn& in) const;

  using ItemPtr = std::shared_ptr<WriteItem>;

  // ---- mill_store_impl.cc
  // Validates `item` against spec_ and records it there. *immediate: an
  // idempotent repeat of something already committed (answer at once).
  Status AdmitLocked(WriteItem* item, bool* immediate);
  // The coil stored or queued under `coil_id`; *pending when queued. Reads
  // the database only when committed_coil_ids_ may contain the id.
  StatusOr<std::optional<StoredCoil>> FindCoilLocked(const std::string& coil_id,
                                                     bool* pending);
  // Admits, queues and waits for the commit; *immediate as above.
  // Queues `item` for the writer (Submit then waits for it). Refused or
  // answered at admission (*immediate): nothing is queued.
  Status Enqueue(const ItemPtr& item, bool* immediate);
  // A coil write item, or the error of its fields (AddCoil, AddCoilAsync).
  StatusOr<ItemPtr> CoilItem(const CoilIn& in) const;
  Status Submit(const ItemPtr& item, bool* immediate);
  Status RunTask(std::function<Status(Db*)> task,
                 std::function<void(Db*)> after_commit);
  // The answer to a repeat of a stored coil: its first answer, read from
  // the coil's row (O(passes)); replayed under the current model only if
  // the row has none (cannot happen after Init's backfill).
  CoilOutcome OutcomeForStored(const StoredCoil& coil) const;
  std::shared_ptr<const ModelVersion> MakePrior(uint32_t positions_seen) const;
  // Mounted() with mu_ held.
  MountedState MountedLocked() const;

  // ---- store_limits.cc
  // Reads the wear_limits table into api_limits_ (Init).
  Status LoadWearLimits(Db* db);
  // The limit in force at `slot`: api_limits_, else the configuration's.
  WearLimit LimitLocked(int slot) const;

  // ---- mill_store_calibration.cc
  // Records a calibration run (claimed at once when `claim`); returns its id.
  StatusOr<int64_t> InsertRun(const std::string& trigger,
                              const std::string& model, int option, bool claim);
  // Runs `claim` in a write transaction; it returns whether it claimed a
  // run, and once that has committed the count of measurements since the
  // last calibration restarts. Returns what `claim` returned.
  StatusOr<bool> ClaimTask(const std::function<StatusOr<bool>(Db*)>& claim);
  std::shared_ptr<const ModelVersion> ActiveVersion() const;

  // ---- mill_store_writer.cc
  void WriterLoop();
  // Group commit: while the queue holds fewer writes than callers recently
  // had in flight, waits (at most kMaxLinger) for the rest to arrive, so
  // one fsync serves them all. Called with mu_ held via `lock`.
  void LingerLocked(std::unique_lock<std::mutex>* lock);
  // Computes, on `state`, what the batch's roll changes, ends and coils do
  // to the predictions; fills each new coil's answer (coil_outcome and
  // coil_wear). Writer thread, no lock held.
  void PredictBatch(const std::vector<ItemPtr>& batch, LiveState* state) const;
  Status ExecuteItem(WriteItem* item);
  // After a commit: applies the batch to committed_ and installs `next`
  // (PredictBatch's result; empty for imports and tasks).
  void PublishBatch(const std::vector<ItemPtr>& batch,
                    std::optional<LiveState> next);
  // After a failed commit: fails the batch, rebuilds spec_ from committed_
  // and the still-queued writes (re-validated; those now invalid are
  // answered with their error and returned in *finished).
  void FailBatch(const std::vector<ItemPtr>& batch, const Status& error,
                 std::vector<ItemPtr>* finished);
  // Replays the open campaign's stored passes under `model` and installs
  // model and roll states together (writer thread or Init). `model` is the
  // version as stored; the served one has its rolls' factors re-estimated
  // from their readings (store_roll_factors.cc) unless `served` is set,
  // when `model` is already the served model of the stored version active.
  // Publishes a committed import to the catalog and the counters (mu_
  // held); true when the prior must be rebuilt for new positions.
  bool PublishImportLocked(const WriteItem& item);
  void InstallModel(std::shared_ptr<const ModelVersion> model,
                    bool served = false);
  // After a commit that stored readings of `rolls` (every roll when
  // `all`): re-estimates their factors in the served model and installs it.
  void RefreshRollFactors(const std::set<std::string>& rolls, bool all);

  const StoreOptions options_;
  const WearPredictor& predictor_ = *options_.predictor;
  std::string path_;
  std::unique_ptr<Db> writer_db_;
  std::unique_ptr<Db> lookup_db_;
  mutable std::mutex read_mu_;
  std::unique_ptr<Db> read_db_;
  mutable std::mutex publish_mu_;

  mutable std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::deque<ItemPtr> queue_;
  Catalog committed_;
  CoilIdFilter committed_coil_ids_;
  Catalog spec_;
  // Published whole after each commit that changes it, never changed in
  // place (Mounted hands it out).
  std::shared_ptr<const RollSlots> rolls_ = std::make_shared<RollSlots>();
  // The active model: as stored (ActiveModel, the promotion gate) and as
  // served (predictions; the per-roll factors updated by their readings,
  // store_roll_factors.cc). The same object without a roll-effect term.
  std::shared_ptr<const ModelVersion> stored_model_;
  std::shared_ptr<const ModelVersion> model_;
  // Wear limits set through SetWearLimit (mu_), by slot.
  std::array<std::optional<WearLimit>, kNumRollPositionSlots> api_limits_;
  StoreCounters counters_;
  // Group-commit pacing (mu_): writes queued or being committed, their
  // maximum over the current and the previous window, and the queue length
  // at which a caller wakes the writer.
  int in_flight_ = 0;
  int peak_in_flight_ = 0;
  int peak_in_flight_prev_ = 0;
  std::chrono::steady_clock::time_point peak_window_start_;
  size_t wake_writer_at_ = 1;
  std::thread writer_;
  // Serialises hand activations and recorded promotions, so that each
  // promotion replaces the version its run was compared with and a run never
  // promotes over a fresh pin (FinishCalibration, ActivateModel).
  std::mutex promote_mu_;
};

// What the grinder is expected to read on top of the wear for the stored
// measurement of `slot` of the ended campaign `rec` under `model`: its
// measurement terms (WearPredictor::ReadingOffset), the offset validation
// adds. 0 when the slot is unmeasured or the campaign open
// (mill_store_history.cc).
double StoredReadingOffset(const WearPredictor& predictor,
                           const WearModel& model, const CampaignRec& rec,
                           int slot);

// The ended campaigns of `catalog` with a plausible reading of one of
// `rolls` (of any roll when empty), copied (store_roll_factors.cc).
std::vector<CampaignRec> MeasuredCampaignsOf(const Catalog& catalog,
                                             const std::set<std::string>& rolls);
// `model` with its roll-effect term's levels re-estimated from the
// plausible readings (WearPredictor::WithRollFactors) of `rolls` (of
// every measured roll when empty) in `campaigns` (MeasuredCampaignsOf),
// each campaign replayed under `model`; `model` itself when it has no
// roll-effect term (or a grade-scoped one) or no such reading. A roll
// whose readings give no converged estimate keeps its level.
StatusOr<std::shared_ptr<const ModelVersion>> WithRollReadings(
    Db* db, const WearPredictor& predictor,
    const std::vector<CampaignRec>& campaigns,
    std::shared_ptr<const ModelVersion> model,
    const std::set<std::string>& rolls);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_MILL_STORE_IMPL_H_
