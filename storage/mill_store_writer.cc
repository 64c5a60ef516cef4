// The group-commit writer of MillStore: one thread takes up to max_batch
// queued writes, writes them in ONE transaction (synchronous=FULL: one
// fsync for the batch), commits, then publishes them to the in-memory state
// and wakes their callers. A failed transaction is rolled back whole; its
// callers get the error and the speculative state is rebuilt without it.
#include <utility>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"
#include "storage/validation.h"

namespace rollwear::storage::internal {
namespace {

bool IsExclusive(WriteKind k) {
  return k == WriteKind::kImport || k == WriteKind::kTask;
}

}  // namespace

void MillStoreImpl::WriterLoop() {
  while (true) {
    std::vector<ItemPtr> batch;
    {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      const bool exclusive = IsExclusive(queue_.front()->kind);
      do {
        batch.push_back(std::move(queue_.front()));
        queue_.pop_front();
      } while (!exclusive && !queue_.empty() &&
               static_cast<int>(batch.size()) < options_.max_batch &&
               !IsExclusive(queue_.front()->kind));
    }

    bool needs_write = false;
    for (const ItemPtr& item : batch) needs_write |= !item->unchanged;
    Status status;
    if (needs_write) {
      StatusOr<Transaction> txn = Transaction::Begin(writer_db_.get());
      status = txn.status();
      for (size_t i = 0; status.ok() && i < batch.size(); ++i) {
        if (!batch[i]->unchanged) status = ExecuteItem(batch[i].get());
      }
      if (status.ok()) status = txn->Commit();
      // On error the Transaction's destructor rolls back.
    }

    std::vector<ItemPtr> finished = batch;
    if (status.ok()) {
      if (needs_write) {
        std::lock_guard<std::mutex> lock(mu_);
        ++counters_.commits;
      }
      PublishBatch(batch);
    } else {
      FailBatch(batch, status, &finished);
    }
    for (const ItemPtr& item : finished) {
      if (item->status.ok() && item->kind == WriteKind::kCoil &&
          item->unchanged) {
        item->coil_outcome = OutcomeForStored(item->coil);
      }
      item->done.set_value();
    }
  }
}

Status MillStoreImpl::ExecuteItem(WriteItem* item) {
  Db* db = writer_db_.get();
  switch (item->kind) {
    case WriteKind::kRollChange: {
      const RollChangeIn& in = item->roll_change;
      ROLLWEAR_RETURN_IF_ERROR(EndOpenCampaigns(db, in.started_at));
      StatusOr<int64_t> row =
          InsertCampaign(db, in.campaign_id, in.started_at, std::nullopt, "");
      if (!row.ok()) return row.status();
      for (const MountedRollIn& m : in.rolls) {
        ROLLWEAR_RETURN_IF_ERROR(InsertMount(db, *row, m, ""));
      }
      return Status::Ok();
    }
    case WriteKind::kEndCampaign:
      return SetCampaignEnded(db, item->campaign_id, item->ended_at);
    case WriteKind::kCoil:
      return InsertCoilWithPasses(db, item->coil);
    case WriteKind::kMeasurement: {
      StatusOr<int64_t> row = CampaignRow(db, item->measurement.campaign_id);
      if (!row.ok()) return row.status();
      return InsertMeasurement(db, *row, item->measurement, "");
    }
    case WriteKind::kImport:
      return WriteImport(db, *item->dataset, item->dataset_coils, item->plan);
    case WriteKind::kTask:
      return item->task(db);
  }
  return Status::Internal("unknown write kind");
}

void MillStoreImpl::PublishBatch(const std::vector<ItemPtr>& batch) {
  bool replay_open = false;
  std::vector<WriteItem*> tasks;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const ItemPtr& ptr : batch) {
      WriteItem* item = ptr.get();
      if (item->unchanged) continue;
      switch (item->kind) {
        case WriteKind::kRollChange: {
          const uint32_t seen = committed_.positions_seen;
          ::rollwear::storage::internal::ApplyRollChange(item->roll_change,
                                                         &committed_);
          ++counters_.campaigns;
          if (model_->version == 0 && committed_.positions_seen != seen) {
            model_ = MakePrior(committed_.positions_seen);
          }
          for (auto& r : rolls_) r.reset();
          for (const MountedRollIn& m : item->roll_change.rolls) {
            rolls_[RollPositionSlot(m.stand, m.position)] =
                LiveRoll{m, MountRoll(model_->wear_model,
                                      RollPositionName(m.stand, m.position),
                                      m.roll_type, m.diameter_mm, m.hardness_hb,
                                      item->roll_change.started_at)};
          }
          break;
        }
        case WriteKind::kEndCampaign:
          if (committed_.open_campaign == item->campaign_id) {
            for (auto& r : rolls_) r.reset();
          }
          ApplyEnd(item->campaign_id, item->ended_at, &committed_);
          break;
        case WriteKind::kCoil: {
          const StoredCoil& coil = item->coil;
          ApplyCoil(coil, /*speculative=*/false, &committed_);
          spec_.pending_coils.erase(coil.coil_id);
          ++counters_.coils;
          CoilOutcome& out = item->coil_outcome;
          out.outcome = WriteOutcome::kCreated;
          if (committed_.open_campaign != coil.campaign_id) break;
          for (const StoredPass& p : coil.passes) {
            const PassInput in = ToPassInput(coil.grade, p);
            for (Position pos : {Position::kTop, Position::kBottom}) {
              auto& roll = rolls_[RollPositionSlot(p.stand, pos)];
              if (!roll) continue;
              const double wear = AddPass(model_->wear_model, in, &roll->state);
              out.added.push_back(CoilOutcome::Added{p.stand, pos,
                                                     roll->mount.roll_id, wear,
                                                     roll->state.wear_um});
            }
          }
          break;
        }
        case WriteKind::kMeasurement:
          ApplyMeasurement(item->measurement, &committed_);
          ++counters_.measurements;
          ++counters_.measurements_since_last_calibration;
          break;
        case WriteKind::kImport: {
          const uint32_t seen = committed_.positions_seen;
          ApplyImport(*item->dataset, item->dataset_coils, item->plan,
                      /*speculative=*/false, &committed_);
          for (size_t i = 0; i < item->dataset_coils.size(); ++i) {
            if (item->plan.new_coil[i]) {
              spec_.pending_coils.erase(item->dataset_coils[i].coil_id);
            }
          }
          counters_.campaigns += item->plan.num_campaigns;
          counters_.coils += item->plan.num_coils;
          counters_.measurements += item->plan.num_measurements;
          counters_.measurements_since_last_calibration +=
              item->plan.num_measurements;
          replay_open = replay_open || (model_->version == 0 &&
                                        committed_.positions_seen != seen);
          break;
        }
        case WriteKind::kTask:
          tasks.push_back(item);
          break;
      }
    }
  }
  if (replay_open) {
    std::shared_ptr<const ModelVersion> prior;
    {
      std::lock_guard<std::mutex> lock(mu_);
      prior = MakePrior(committed_.positions_seen);
    }
    InstallModel(std::move(prior));
  }
  for (WriteItem* task : tasks) {
    if (task->after_commit) task->after_commit(writer_db_.get());
  }
}

void MillStoreImpl::FailBatch(const std::vector<ItemPtr>& batch,
                              const Status& error,
                              std::vector<ItemPtr>* finished) {
  std::lock_guard<std::mutex> lock(mu_);
  for (const ItemPtr& item : batch) item->status = error;
  // Nothing of the batch is in the database: start again from what is, and
  // re-admit the writes still queued (some may have relied on the batch).
  spec_ = committed_;
  std::deque<ItemPtr> keep;
  for (ItemPtr& item : queue_) {
    bool immediate = false;
    item->status = AdmitLocked(item.get(), &immediate);
    if (!item->status.ok() || immediate) {
      finished->push_back(std::move(item));
    } else {
      keep.push_back(std::move(item));
    }
  }
  queue_ = std::move(keep);
}

void MillStoreImpl::InstallModel(std::shared_ptr<const ModelVersion> model) {
  CampaignRec open;
  bool has_open = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    has_open = !committed_.open_campaign.empty();
    if (has_open) open = committed_.campaigns.at(committed_.open_campaign);
  }
  RollStates states;
  if (has_open) {
    StatusOr<RollStates> replay =
        ReplayCampaign(writer_db_.get(), open, model->wear_model);
    if (replay.ok()) {
      states = std::move(replay).value();
    } else {
      // The committed passes could not be read back (should not happen:
      // this is the writer's own connection). Keep the mounts fresh rather
      // than mixing two models in one state.
      for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
        const auto& m = open.mounts[slot];
        if (!m) continue;
        states[slot] = MountRoll(
            model->wear_model, RollPositionName(m->stand, m->position),
            m->roll_type, m->diameter_mm, m->hardness_hb, open.started_at);
      }
    }
  }
  std::lock_guard<std::mutex> lock(mu_);
  model_ = std::move(model);
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (has_open && open.mounts[slot] && states[slot]) {
      rolls_[slot] = LiveRoll{*open.mounts[slot], std::move(*states[slot])};
    } else {
      rolls_[slot].reset();
    }
  }
}

}  // namespace rollwear::storage::internal
