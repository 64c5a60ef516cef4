// MillStore: opening, admission of writes (validation against the
// speculative catalog), the write entry points, and the read side.
#include "storage/mill_store_impl.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <utility>

#include "storage/model_levels.h"
#include "storage/schema.h"
#include "storage/store_quality.h"
#include "storage/store_sql.h"
#include "storage/validation.h"

namespace rollwear::storage {

StatusOr<std::unique_ptr<MillStore>> MillStore::Open(
    const std::string& path, const StoreOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) {
    return Status::InvalidArgument("store options: " + error);
  }
  if (options.predictor == nullptr) {
    return Status::InvalidArgument(
        "store options: no predictor (open the store with engine::OpenStore)");
  }
  auto store = std::make_unique<internal::MillStoreImpl>(options);
  ROLLWEAR_RETURN_IF_ERROR(store->Init(path));
  return std::unique_ptr<MillStore>(std::move(store));
}

namespace internal {

Status MillStoreImpl::Init(const std::string& path) {
  path_ = path;
  ROLLWEAR_ASSIGN_OR_RETURN(writer_db_, Db::Open(path));
  ROLLWEAR_RETURN_IF_ERROR(MigrateSchema(writer_db_.get()));
  ROLLWEAR_RETURN_IF_ERROR(
      FailInterruptedCalibrations(writer_db_.get(), NowSeconds()));
  ROLLWEAR_ASSIGN_OR_RETURN(lookup_db_, Db::Open(path));
  ROLLWEAR_ASSIGN_OR_RETURN(read_db_, Db::Open(path));

  ROLLWEAR_ASSIGN_OR_RETURN(committed_, LoadCatalog(writer_db_.get()));
  spec_ = committed_;
  ROLLWEAR_RETURN_IF_ERROR(LoadWearLimits(writer_db_.get()));
  ROLLWEAR_ASSIGN_OR_RETURN(const StoredCounts counts,
                            LoadCounts(writer_db_.get()));
  counters_.campaigns = counts.campaigns;
  counters_.coils = counts.coils;
  counters_.measurements = counts.measurements;
  counters_.measurements_since_last_calibration =
      counts.measurements_since_last_calibration;
  counters_.suspect_measurements = counts.suspect_measurements;
  committed_coil_ids_.Reserve(static_cast<size_t>(counts.coils));
  ROLLWEAR_RETURN_IF_ERROR(ForEachCoilId(
      writer_db_.get(),
      [this](const std::string& id) { committed_coil_ids_.Insert(id); }));

  ROLLWEAR_ASSIGN_OR_RETURN(std::optional<ModelVersion> active,
                            LoadActiveModel(writer_db_.get()));
  std::shared_ptr<const ModelVersion> model =
      active.has_value()
          ? std::make_shared<const ModelVersion>(std::move(*active))
          : MakePrior(committed_.positions_seen);
  // Coils without a stored answer (from a version-1 file, or an import
  // interrupted before schema version 2) get one, under the active model.
  {
    ROLLWEAR_ASSIGN_OR_RETURN(Transaction txn,
                              Transaction::Begin(writer_db_.get()));
    ROLLWEAR_ASSIGN_OR_RETURN(const int filled,
                              BackfillCoilWear(writer_db_.get(), predictor_,
                                               committed_, model->wear_model));
    if (filled > 0) {
      ROLLWEAR_RETURN_IF_ERROR(txn.Commit());
    }
  }
  InstallModel(std::move(model));
  peak_window_start_ = std::chrono::steady_clock::now();
  writer_ = std::thread([this] { WriterLoop(); });
  return Status::Ok();
}

MillStoreImpl::~MillStoreImpl() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (writer_.joinable()) writer_.join();
}

std::shared_ptr<const ModelVersion> MillStoreImpl::MakePrior(
    uint32_t positions_seen) const {
  std::vector<std::string> labels = PositionLabels(positions_seen);
  if (labels.empty())
    labels = PositionLabels((1u << kNumRollPositionSlots) - 1);
  StatusOr<WearModel> wm =
      PriorModel(options_.default_law, options_.default_option,
                 std::move(labels), options_.initial_k);
  auto v = std::make_shared<ModelVersion>();
  v->version = 0;
  v->model = WearLawName(options_.default_law);
  v->option = options_.default_option;
  v->active = true;
  if (wm.ok()) v->wear_model = std::move(wm).value();  // valid options: ok
  return v;
}

// ------------------------------------------------------------- admission

StatusOr<std::optional<StoredCoil>> MillStoreImpl::FindCoilLocked(
    const std::string& coil_id, bool* pending) {
  auto it = spec_.pending_coils.find(coil_id);
  *pending = it != spec_.pending_coils.end();
  if (*pending) return std::optional<StoredCoil>(it->second);
  // Not stored for certain: no SQLite read under mu_ for a new coil.
  if (!committed_coil_ids_.MayContain(coil_id)) {
    return std::optional<StoredCoil>();
  }
  return LookupCoil(lookup_db_.get(), coil_id);
}

Status MillStoreImpl::AdmitLocked(WriteItem* item, bool* immediate) {
  *immediate = false;
  bool unchanged = false;
  switch (item->kind) {
    case WriteKind::kRollChange: {
      ROLLWEAR_RETURN_IF_ERROR(
          AdmitRollChange(spec_, item->roll_change, &unchanged));
      if (!unchanged) {
        ::rollwear::storage::internal::ApplyRollChange(item->roll_change,
                                                       &spec_);
      } else {
        bool committed = false;
        *immediate =
            AdmitRollChange(committed_, item->roll_change, &committed).ok() &&
            committed;
      }
      break;
    }
    case WriteKind::kEndCampaign: {
      ROLLWEAR_RETURN_IF_ERROR(
          AdmitEnd(spec_, item->campaign_id, item->ended_at, &unchanged));
      if (!unchanged) {
        ApplyEnd(item->campaign_id, item->ended_at, &spec_);
      } else {
        bool committed = false;
        *immediate =
            AdmitEnd(committed_, item->campaign_id, item->ended_at, &committed)
                .ok() &&
            committed;
      }
      break;
    }
    case WriteKind::kCoil: {
      bool pending = false;
      ROLLWEAR_ASSIGN_OR_RETURN(const std::optional<StoredCoil> stored,
                                FindCoilLocked(item->coil.coil_id, &pending));
      ROLLWEAR_RETURN_IF_ERROR(
          AdmitCoil(spec_, item->coil_in, item->coil, stored, &unchanged));
      if (!unchanged) {
        ApplyCoil(item->coil, /*speculative=*/true, &spec_);
      } else {
        *immediate = !pending;
      }
      break;
    }
    case WriteKind::kMeasurement: {
      ROLLWEAR_RETURN_IF_ERROR(
          AdmitMeasurement(spec_, item->measurement, &unchanged));
      if (!unchanged) {
        ApplyMeasurement(item->measurement, &spec_);
      } else {
        bool committed = false;
        *immediate =
            AdmitMeasurement(committed_, item->measurement, &committed).ok() &&
            committed;
      }
      break;
    }
    case WriteKind::kImport: {
      auto lookup_coil = [this](const std::string& id) {
        bool pending = false;
        return FindCoilLocked(id, &pending);
      };
      auto lookup_seq = [this](const std::string& campaign, int seq) {
        return LookupSeq(lookup_db_.get(), campaign, seq);
      };
      ROLLWEAR_ASSIGN_OR_RETURN(
          item->plan,
          PlanImport(*item->dataset, item->lines, item->dataset_coils, spec_,
                     lookup_coil, lookup_seq));
      ApplyImport(*item->dataset, item->dataset_coils, item->plan,
                  /*speculative=*/true, &spec_);
      break;
    }
    case WriteKind::kTask:
      break;
  }
  item->unchanged = unchanged;
  return Status::Ok();
}

Status MillStoreImpl::Enqueue(const ItemPtr& item, bool* immediate) {
  bool notify = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (stop_) return Status::Unavailable("the store is shutting down");
    ROLLWEAR_RETURN_IF_ERROR(AdmitLocked(item.get(), immediate));
    if (*immediate) return Status::Ok();
    queue_.push_back(item);
    ++in_flight_;
    peak_in_flight_ = std::max(peak_in_flight_, in_flight_);
    // While the writer lingers for more writes, wake it only once enough
    // are queued, or for a write that ends its wait (LingerLocked).
    notify = queue_.size() >= wake_writer_at_ || EndsLinger(item->kind);
  }
  if (notify) cv_.notify_one();
  return Status::Ok();
}

Status MillStoreImpl::Submit(const ItemPtr& item, bool* immediate) {
  std::future<void> done = item->done.get_future();
  ROLLWEAR_RETURN_IF_ERROR(Enqueue(item, immediate));
  if (*immediate) return Status::Ok();
  done.wait();
  return item->status;
}

Status MillStoreImpl::RunTask(std::function<Status(Db*)> task,
                              std::function<void(Db*)> after_commit) {
  auto item = std::make_shared<WriteItem>();
  item->kind = WriteKind::kTask;
  item->task = std::move(task);
  item->after_commit = std::move(after_commit);
  bool immediate = false;
  return Submit(item, &immediate);
}

// ---------------------------------------------------------------- writes

StatusOr<WriteOutcome> MillStoreImpl::ApplyRollChange(const RollChangeIn& in) {
  if (!in.rules_checked) ROLLWEAR_RETURN_IF_ERROR(CheckRollChangeFields(in));
  auto item = std::make_shared<WriteItem>();
  item->kind = WriteKind::kRollChange;
  item->roll_change = in;
  bool immediate = false;
  ROLLWEAR_RETURN_IF_ERROR(Submit(item, &immediate));
  return item->unchanged ? WriteOutcome::kUnchanged : WriteOutcome::kCreated;
}

StatusOr<WriteOutcome> MillStoreImpl::EndCampaign(
    const std::string& campaign_id, UnixSeconds ended_at) {
  ROLLWEAR_RETURN_IF_ERROR(CheckEndFields(campaign_id, ended_at));
  auto item = std::make_shared<WriteItem>();
  item->kind = WriteKind::kEndCampaign;
  item->campaign_id = campaign_id;
  item->ended_at = ended_at;
  bool immediate = false;
  ROLLWEAR_RETURN_IF_ERROR(Submit(item, &immediate));
  return item->unchanged ? WriteOutcome::kUnchanged : WriteOutcome::kCreated;
}

StatusOr<MillStoreImpl::ItemPtr> MillStoreImpl::CoilItem(
    const CoilIn& in) const {
  if (!in.rules_checked) ROLLWEAR_RETURN_IF_ERROR(CheckCoilFields(in));
  auto item = std::make_shared<WriteItem>();
  item->kind = WriteKind::kCoil;
  item->coil_in = in;
  item->coil = CanonicalCoil(in);
  return item;
}

StatusOr<CoilOutcome> MillStoreImpl::AddCoil(const CoilIn& in) {
  ROLLWEAR_ASSIGN_OR_RETURN(const ItemPtr item, CoilItem(in));
  bool immediate = false;
  ROLLWEAR_RETURN_IF_ERROR(Submit(item, &immediate));
  if (immediate) return OutcomeForStored(item->coil);
  return item->coil_outcome;
}

void MillStoreImpl::AddCoilAsync(const CoilIn& in, CoilDone done,
                                 const Executor& blocking) {
  StatusOr<ItemPtr> made = CoilItem(in);
  if (!made.ok()) {
    done(made.status());
    return;
  }
  ItemPtr item = std::move(made).value();
  // The writer calls this once the item is finished; the item owns the
  // callback, and the callback sees the item through a raw pointer (no
  // cycle: the writer drops its reference after the call).
  WriteItem* raw = item.get();
  item->on_done = [raw, done] {
    if (raw->status.ok()) {
      done(raw->coil_outcome);
    } else {
      done(raw->status);
    }
  };
  bool immediate = false;
  const Status queued = Enqueue(item, &immediate);
  if (!queued.ok()) {
    done(queued);
  } else if (immediate) {
    blocking([this, coil = std::move(item->coil), done = std::move(done)] {
      done(OutcomeForStored(coil));
    });
  }
}

StatusOr<WriteOutcome> MillStoreImpl::AddMeasurement(const MeasurementIn& in,
                                                     std::string* suspect) {
  if (!in.rules_checked) ROLLWEAR_RETURN_IF_ERROR(CheckMeasurementFields(in));
  auto item = std::make_shared<WriteItem>();
  item->kind = WriteKind::kMeasurement;
  item->measurement = in;
  // A new key is judged among the readings of the kJudgedCampaigns most
  // recent campaigns (and of its own when older) with the exposures the
  // committed catalog keeps, so its cost neither grows with the mill's
  // history nor reads the database: re-reading those campaigns' passes for
  // each reading made the daemon's replay of a 790-campaign mill CPU-bound
  // on SQLite. A stored key is a repeat or a conflict, which Submit tells
  // apart: not judged again.
  if (!StoredSuspect(in).has_value()) {
    std::vector<ReadingExposure> readings;
    {
      std::lock_guard<std::mutex> lock(mu_);
      readings = JudgedReadings(committed_, in, kJudgedCampaigns);
    }
    item->measurement.suspect = JudgeMeasurement(readings);
  }
  bool immediate = false;
  ROLLWEAR_RETURN_IF_ERROR(Submit(item, &immediate));
  if (suspect != nullptr) {
    *suspect = item->measurement.suspect;
    if (item->unchanged) *suspect = StoredSuspect(in).value_or("");
  }
  return item->unchanged ? WriteOutcome::kUnchanged : WriteOutcome::kCreated;
}

std::optional<std::string> MillStoreImpl::StoredSuspect(
    const MeasurementIn& in) const {
  std::lock_guard<std::mutex> lock(mu_);
  for (const Catalog* c : {&committed_, &spec_}) {
    auto it = c->campaigns.find(in.campaign_id);
    if (it == c->campaigns.end()) continue;
    const auto& m =
        it->second.measurements[RollPositionSlot(in.stand, in.position)];
    if (m.has_value()) return m->suspect;
  }
  return std::nullopt;
}

Status MillStoreImpl::ImportDataset(const Dataset& data,
                                    const DatasetLines* lines,
                                    ImportCounts* counts) {
  ROLLWEAR_RETURN_IF_ERROR(CheckDataset(data));
  auto item = std::make_shared<WriteItem>();
  item->kind = WriteKind::kImport;
  item->dataset = &data;
  item->lines = lines;
  item->dataset_coils = DatasetCoils(data);
  item->dataset_suspect = SuspectFlags(AssessDataQuality(data));
  bool immediate = false;
  ROLLWEAR_RETURN_IF_ERROR(Submit(item, &immediate));
  if (counts != nullptr) *counts = CountImport(item->plan);
  return Status::Ok();
}

CoilOutcome MillStoreImpl::OutcomeForStored(const StoredCoil& coil) const {
  CoilOutcome out;
  out.outcome = WriteOutcome::kUnchanged;
  std::shared_ptr<const ModelVersion> model;
  CampaignRec rec;
  {
    std::lock_guard<std::mutex> lock(mu_);
    auto it = committed_.campaigns.find(coil.campaign_id);
    if (it == committed_.campaigns.end()) return out;
    model = model_;
    rec = it->second;
  }
  // The coil's first answer, stored with it: what it added and each roll's
  // total right after it, under the model active when it was stored.
  std::vector<CoilWearEntry> entries;
  StatusOr<std::optional<std::string>> blob = std::optional<std::string>();
  {
    std::lock_guard<std::mutex> lock(read_mu_);
    blob = LookupCoilWear(read_db_.get(), coil.coil_id);
  }
  bool have =
      blob.ok() && blob->has_value() && DecodeCoilWear(**blob, &entries);
  if (!have) {
    // No stored answer (not expected: Init and imports fill them in):
    // replay the campaign under the current model up to this coil.
    std::lock_guard<std::mutex> lock(read_mu_);
    StatusOr<RollStates> replay =
        ReplayCampaignCoils(read_db_.get(), predictor_, rec, model->wear_model,
                            [&](const ReplayedCoil& c) -> Status {
                              if (c.coil_id == coil.coil_id) {
                                entries = c.entries;
                                have = true;
                              }
                              return Status::Ok();
                            });
    if (!replay.ok()) have = false;
  }
  if (!have) return out;
  for (const CoilWearEntry& e : entries) {
    const auto& mount = rec.mounts[e.slot];
    out.added.push_back(
        CoilOutcome::Added{SlotStand(e.slot), SlotPosition(e.slot),
                           mount.has_value() ? mount->roll_id : std::string(),
                           e.wear_um, e.total_um});
  }
  return out;
}

// ----------------------------------------------------------------- reads

MountedState MillStoreImpl::Mounted() const {
  std::lock_guard<std::mutex> lock(mu_);
  return MountedLocked();
}

MountedState MillStoreImpl::MountedLocked() const {
  MountedState out;
  out.model = model_;
  out.campaign_id = committed_.open_campaign;
  out.rolls = rolls_;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if ((*rolls_)[slot]) out.wear_limit_um[slot] = LimitLocked(slot).limit_um;
  }
  return out;
}

StatusOr<Dataset> MillStoreImpl::ExportDataset() const {
  // A connection of its own: a long read must not hold up the small ones.
  DbOptions o;
  o.read_only = true;
  ROLLWEAR_ASSIGN_OR_RETURN(const std::unique_ptr<Db> db, Db::Open(path_, o));
  return ReadStoredDataset(db.get());
}

StatusOr<FittingData> MillStoreImpl::ReadFittingData() const {
  DbOptions o;
  o.read_only = true;
  ROLLWEAR_ASSIGN_OR_RETURN(const std::unique_ptr<Db> db, Db::Open(path_, o));
  std::vector<std::string> flags;
  ROLLWEAR_ASSIGN_OR_RETURN(Dataset all, ReadStoredDataset(db.get(), &flags));
  return FittingDataOf(std::move(all), flags);
}

StoreCounters MillStoreImpl::Counters() const {
  std::lock_guard<std::mutex> lock(mu_);
  return counters_;
}

bool MillStoreImpl::Healthy() const {
  std::lock_guard<std::mutex> lock(read_mu_);
  return read_db_->Exec("SELECT 1").ok();
}

}  // namespace internal
}  // namespace rollwear::storage
