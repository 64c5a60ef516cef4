// The group-commit writer of MillStore: one thread takes up to max_batch
// queued writes, writes them in ONE transaction (synchronous=FULL: one
// fsync for the batch), commits, then publishes them to the in-memory state
// and wakes their callers. A failed transaction is rolled back whole; its
// callers get the error and the speculative state is rebuilt without it.
//
// Batching: a closed-loop client posts its next coil only after the answer
// to the previous one, so the writes that arrive during one commit are
// only those of the clients not in it. Committing at once would split N
// clients into many small groups and make the disk's fsync rate the limit
// in coils/s; waiting for all N would leave the cores idle during every
// fsync (all callers would be inside the commit). The writer waits - at
// most kMaxLinger - until half of the callers recently in flight are
// queued: N clients settle into two groups of N/2 that alternate, one
// being committed while the other's requests are decoded, validated and
// answered. A lone client never waits (one in flight, one queued); a caller
// that stops posting costs one linger, after which the expected count
// follows what arrives. A roll change or a campaign end never waits: what
// follows it waits for its answer (a 1 ms linger at each of them made a
// replay's barriers cost a third of its time).
//
// Predictions: before the transaction, PredictBatch computes on a copy of
// the live state what the batch's coils add (each coil's answer is stored
// with it, coils.wear); after the commit the copy is installed. Only this
// thread changes the live state, so the copy cannot go stale.
#include <algorithm>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "storage/extra_json.h"
#include "storage/mill_store_impl.h"
#include "storage/store_quality.h"
#include "storage/store_sql.h"
#include "storage/validation.h"

namespace rollwear::storage::internal {
namespace {

// Longest wait for more writes before a commit. Bounds the latency a
// commit can add (an fsync on this class of machine takes ~0.2 ms).
constexpr auto kMaxLinger = std::chrono::microseconds(1000);
// Callers in flight are committed in this many alternating groups.
constexpr int kLingerGroups = 2;
// Window over which the in-flight peak is remembered.
constexpr auto kPeakWindow = std::chrono::milliseconds(100);

// Whether a batch changes predictions (so PredictBatch runs for it).
bool NeedsPrediction(const std::vector<std::shared_ptr<WriteItem>>& batch) {
  for (const auto& item : batch) {
    if (item->unchanged) continue;
    if (item->kind == WriteKind::kCoil ||
        item->kind == WriteKind::kRollChange ||
        item->kind == WriteKind::kEndCampaign) {
      return true;
    }
  }
  return false;
}

}  // namespace

void MillStoreImpl::LingerLocked(std::unique_lock<std::mutex>* lock) {
  const auto now = std::chrono::steady_clock::now();
  if (now - peak_window_start_ > kPeakWindow) {
    peak_in_flight_prev_ = peak_in_flight_;
    peak_in_flight_ = in_flight_;
    peak_window_start_ = now;
  }
  const int peak = std::max(peak_in_flight_, peak_in_flight_prev_);
  const size_t target = static_cast<size_t>(
      std::min(options_.max_batch, (peak + kLingerGroups - 1) / kLingerGroups));
  if (queue_.size() >= target || IsExclusive(queue_.front()->kind)) return;
  if (IsBarrier(queue_.back()->kind)) {
    // Commit at once; the burst before it is over.
    peak_in_flight_ = peak_in_flight_prev_ = static_cast<int>(queue_.size());
    return;
  }
  wake_writer_at_ = target;
  const bool filled = cv_.wait_until(*lock, now + kMaxLinger, [&] {
    return stop_ || queue_.size() >= target || EndsLinger(queue_.back()->kind);
  });
  wake_writer_at_ = 1;
  if (!filled) {
    // Fewer callers than remembered: expect what came.
    peak_in_flight_ = peak_in_flight_prev_ = static_cast<int>(queue_.size());
  }
}

void MillStoreImpl::WriterLoop() {
  while (true) {
    std::vector<ItemPtr> batch;
    std::optional<LiveState> next;
    {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      LingerLocked(&lock);
      const bool exclusive = IsExclusive(queue_.front()->kind);
      do {
        batch.push_back(std::move(queue_.front()));
        queue_.pop_front();
      } while (!exclusive && !queue_.empty() &&
               static_cast<int>(batch.size()) < options_.max_batch &&
               !IsExclusive(queue_.front()->kind));
      if (!exclusive && NeedsPrediction(batch)) {
        next.emplace();
        next->model = model_;
        next->rolls = *rolls_;
        next->open_campaign = committed_.open_campaign;
        next->positions_seen = committed_.positions_seen;
      }
    }
    if (next) PredictBatch(batch, &*next);

    bool needs_write = false;
    for (const ItemPtr& item : batch) needs_write |= !item->unchanged;
    // A task that installs a model after its commit (a promotion, an
    // activation) is published as one step: readers of runs and versions
    // wait until the model is installed (publish_mu_, mill_store_impl.h).
    std::unique_lock<std::mutex> publish(publish_mu_, std::defer_lock);
    if (batch.front()->kind == WriteKind::kTask &&
        batch.front()->after_commit) {
      publish.lock();
    }
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
      PublishBatch(batch, std::move(next));
    } else {
      FailBatch(batch, status, &finished);
    }
    if (publish.owns_lock()) publish.unlock();
    {
      std::lock_guard<std::mutex> lock(mu_);
      in_flight_ -= static_cast<int>(finished.size());
    }
    for (const ItemPtr& item : finished) {
      if (!item->status.ok()) {
        item->coil_outcome = CoilOutcome();
      } else if (item->kind == WriteKind::kCoil && item->unchanged) {
        item->coil_outcome = OutcomeForStored(item->coil);
      }
      if (item->on_done) {
        item->on_done();
      } else {
        item->done.set_value();
      }
    }
  }
}

void MillStoreImpl::PredictBatch(const std::vector<ItemPtr>& batch,
                                 LiveState* state) const {
  std::vector<CoilWearEntry> entries;
  for (const ItemPtr& ptr : batch) {
    WriteItem* item = ptr.get();
    if (item->unchanged) continue;
    switch (item->kind) {
      case WriteKind::kRollChange: {
        uint32_t seen = state->positions_seen;
        for (const MountedRollIn& m : item->roll_change.rolls) {
          seen |= 1u << RollPositionSlot(m.stand, m.position);
        }
        if (state->model->version == 0 && seen != state->positions_seen) {
          state->model = MakePrior(seen);
          state->prior_rebuilt = true;
        }
        state->positions_seen = seen;
        state->open_campaign = item->roll_change.campaign_id;
        for (auto& r : state->rolls) r.reset();
        for (const MountedRollIn& m : item->roll_change.rolls) {
          state->rolls[RollPositionSlot(m.stand, m.position)] =
              MountedRoll{m, predictor_.Mount(state->model->wear_model, m,
                                              item->roll_change.started_at,
                                              item->roll_change.extra,
                                              /*track_profile=*/true)};
        }
        break;
      }
      case WriteKind::kEndCampaign:
        if (state->open_campaign == item->campaign_id) {
          for (auto& r : state->rolls) r.reset();
          state->open_campaign.clear();
        }
        break;
      case WriteKind::kCoil: {
        const StoredCoil& coil = item->coil;
        CoilOutcome& out = item->coil_outcome;
        out = CoilOutcome();
        out.outcome = WriteOutcome::kCreated;
        entries.clear();
        if (state->open_campaign == coil.campaign_id) {
          for (const StoredPass& p : coil.passes) {
            const PassInput in = ToPassInput(coil.grade, p);
            for (Position pos : {Position::kTop, Position::kBottom}) {
              const int slot = RollPositionSlot(p.stand, pos);
              auto& roll = state->rolls[slot];
              if (!roll) continue;
              const double wear = predictor_.AddPass(state->model->wear_model,
                                                     in, &roll->state);
              out.added.push_back(CoilOutcome::Added{p.stand, pos,
                                                     roll->mount.roll_id, wear,
                                                     roll->state.wear_um});
              entries.push_back(CoilWearEntry{slot, wear, roll->state.wear_um,
                                              roll->state.rolled_length_m});
            }
          }
        }
        item->coil_wear = EncodeCoilWear(entries);
        break;
      }
      case WriteKind::kMeasurement:
      case WriteKind::kImport:
      case WriteKind::kTask:
        break;
    }
  }
}

Status MillStoreImpl::ExecuteItem(WriteItem* item) {
  Db* db = writer_db_.get();
  switch (item->kind) {
    case WriteKind::kRollChange: {
      const RollChangeIn& in = item->roll_change;
      ROLLWEAR_RETURN_IF_ERROR(EndOpenCampaigns(db, in.started_at));
      ROLLWEAR_ASSIGN_OR_RETURN(
          const int64_t row,
          InsertCampaign(db, in.campaign_id, in.started_at, std::nullopt,
                         ExtraFieldsJson(in.extra)));
      for (const MountedRollIn& m : in.rolls) {
        ROLLWEAR_RETURN_IF_ERROR(
            InsertMount(db, row, m, ExtraFieldsJson(m.extra)));
      }
      return Status::Ok();
    }
    case WriteKind::kEndCampaign:
      return SetCampaignEnded(db, item->campaign_id, item->ended_at);
    case WriteKind::kCoil:
      return InsertCoilWithPasses(db, item->coil, &item->coil_wear);
    case WriteKind::kMeasurement: {
      ROLLWEAR_ASSIGN_OR_RETURN(const int64_t row,
                                CampaignRow(db, item->measurement.campaign_id));
      return InsertMeasurement(db, row, item->measurement,
                               ExtraFieldsJson(item->measurement.extra));
    }
    case WriteKind::kImport: {
      ROLLWEAR_RETURN_IF_ERROR(WriteImport(db, *item->dataset,
                                           item->dataset_coils, item->plan,
                                           item->dataset_suspect));
      // The imported coils' answers, in the same transaction, under the
      // model the import leaves active (imports run alone, so the catalog
      // the backfill needs is the committed one plus this import).
      Catalog catalog;
      std::shared_ptr<const ModelVersion> model;
      {
        std::lock_guard<std::mutex> lock(mu_);
        catalog = committed_;
        model = model_;
      }
      ApplyImport(*item->dataset, item->dataset_coils, item->plan,
                  /*speculative=*/false, &catalog);
      ROLLWEAR_RETURN_IF_ERROR(WriteImportProfiles(
          db, *item->dataset, item->lines, catalog, &item->plan.profiles));
      if (model->version == 0) model = MakePrior(catalog.positions_seen);
      StatusOr<int> filled =
          BackfillCoilWear(db, predictor_, catalog, model->wear_model);
      return filled.status();
    }
    case WriteKind::kTask:
      return item->task(db);
  }
  return Status::Internal("unknown write kind");
}

void MillStoreImpl::PublishBatch(const std::vector<ItemPtr>& batch,
                                 std::optional<LiveState> next) {
  bool replay_open = false;
  std::vector<WriteItem*> tasks;
  std::set<std::string> measured_rolls;  // whose factors their readings move
  bool all_rolls_measured = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const ItemPtr& ptr : batch) {
      WriteItem* item = ptr.get();
      if (item->unchanged) continue;
      switch (item->kind) {
        case WriteKind::kRollChange:
          ::rollwear::storage::internal::ApplyRollChange(item->roll_change,
                                                         &committed_);
          ++counters_.campaigns;
          break;
        case WriteKind::kEndCampaign:
          ApplyEnd(item->campaign_id, item->ended_at, &committed_);
          break;
        case WriteKind::kCoil:
          ApplyCoil(item->coil, /*speculative=*/false, &committed_);
          committed_coil_ids_.Insert(item->coil.coil_id);
          spec_.pending_coils.erase(item->coil.coil_id);
          ++counters_.coils;
          break;
        case WriteKind::kMeasurement: {
          ApplyMeasurement(item->measurement, &committed_);
          const auto& rec = committed_.campaigns.at(item->measurement.campaign_id);
          const auto& mount = rec.mounts[RollPositionSlot(
              item->measurement.stand, item->measurement.position)];
          if (mount.has_value()) measured_rolls.insert(mount->roll_id);
          ++counters_.measurements;
          ++counters_.measurements_since_last_calibration;
          if (!item->measurement.suspect.empty()) {
            ++counters_.suspect_measurements;
          }
          break;
        }
        case WriteKind::kImport:
          all_rolls_measured =
              all_rolls_measured || item->plan.num_measurements > 0;
          replay_open = PublishImportLocked(*item) || replay_open;
          break;
        case WriteKind::kTask:
          tasks.push_back(item);
          break;
      }
    }
    if (next) {
      // The batch's model is the served one, or the prior rebuilt for new
      // positions (which is then the stored one too).
      if (next->prior_rebuilt) stored_model_ = next->model;
      model_ = std::move(next->model);
      rolls_ = std::make_shared<const RollSlots>(std::move(next->rolls));
    }
  }
  if (!measured_rolls.empty() || all_rolls_measured) {
    RefreshRollFactors(measured_rolls, all_rolls_measured);
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

bool MillStoreImpl::PublishImportLocked(const WriteItem& item) {
  const uint32_t seen = committed_.positions_seen;
  ApplyImport(*item.dataset, item.dataset_coils, item.plan,
              /*speculative=*/false, &committed_);
  for (size_t i = 0; i < item.dataset_coils.size(); ++i) {
    if (item.plan.new_coil[i]) {
      committed_coil_ids_.Insert(item.dataset_coils[i].coil_id);
      spec_.pending_coils.erase(item.dataset_coils[i].coil_id);
    }
  }
  counters_.campaigns += item.plan.num_campaigns;
  counters_.coils += item.plan.num_coils;
  counters_.measurements += item.plan.num_measurements;
  counters_.measurements_since_last_calibration += item.plan.num_measurements;
  counters_.suspect_measurements += FlagImported(
      *item.dataset, item.plan, item.dataset_suspect, &committed_);
  return model_->version == 0 && committed_.positions_seen != seen;
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

void MillStoreImpl::RefreshRollFactors(const std::set<std::string>& rolls,
                                       bool all) {
  const std::set<std::string> wanted = all ? std::set<std::string>() : rolls;
  std::shared_ptr<const ModelVersion> model;
  std::vector<CampaignRec> measured;
  bool mounted_now = false;  // an updated roll runs in the open campaign
  {
    std::lock_guard<std::mutex> lock(mu_);
    model = model_;
    if (predictor_.UpdatableRollTerm(model->wear_model) == nullptr) return;
    measured = MeasuredCampaignsOf(committed_, wanted);
    const auto open = committed_.campaigns.find(committed_.open_campaign);
    if (open != committed_.campaigns.end()) {
      for (const auto& m : open->second.mounts) {
        mounted_now = mounted_now ||
                      (m.has_value() && (all || rolls.count(m->roll_id) > 0));
      }
    }
  }
  StatusOr<std::shared_ptr<const ModelVersion>> served =
      WithRollReadings(writer_db_.get(), predictor_, measured, model, wanted);
  // On a read error the factors stay as they were (the readings are
  // stored; the next install re-estimates them).
  if (!served.ok() || *served == model) return;
  if (mounted_now) {
    InstallModel(*served, /*served=*/true);  // the open campaign replayed
    return;
  }
  // The open campaign's rolls keep their factors: their states stand.
  std::lock_guard<std::mutex> lock(mu_);
  model_ = *std::move(served);
}

void MillStoreImpl::InstallModel(std::shared_ptr<const ModelVersion> model,
                                 bool served) {
  CampaignRec open;
  bool has_open = false;
  const bool rolls =
      !served && predictor_.UpdatableRollTerm(model->wear_model) != nullptr;
  std::vector<CampaignRec> measured;
  {
    std::lock_guard<std::mutex> lock(mu_);
    has_open = !committed_.open_campaign.empty();
    if (has_open) open = committed_.campaigns.at(committed_.open_campaign);
    if (rolls) measured = MeasuredCampaignsOf(committed_, {});
  }
  const std::shared_ptr<const ModelVersion> stored = model;
  if (rolls) {
    StatusOr<std::shared_ptr<const ModelVersion>> with =
        WithRollReadings(writer_db_.get(), predictor_, measured, model, {});
    if (with.ok()) model = *std::move(with);  // else: the fitted factors
  }
  RollStates states;
  if (has_open) {
    StatusOr<RollStates> replay =
        ReplayCampaign(writer_db_.get(), predictor_, open, model->wear_model,
                       /*track_profiles=*/true);
    if (replay.ok()) {
      states = std::move(replay).value();
    } else {
      // The committed passes could not be read back (should not happen:
      // this is the writer's own connection). Keep the mounts fresh rather
      // than mixing two models in one state.
      for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
        const auto& m = open.mounts[slot];
        if (!m) continue;
        states[slot] = predictor_.Mount(model->wear_model, *m, open.started_at,
                                        open.extra, /*track_profile=*/true);
      }
    }
  }
  auto installed = std::make_shared<RollSlots>();
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (has_open && open.mounts[slot] && states[slot]) {
      (*installed)[slot] =
          MountedRoll{*open.mounts[slot], std::move(*states[slot])};
    }
  }
  std::lock_guard<std::mutex> lock(mu_);
  if (!served) stored_model_ = stored;
  model_ = std::move(model);
  rolls_ = std::move(installed);
}

}  // namespace rollwear::storage::internal
