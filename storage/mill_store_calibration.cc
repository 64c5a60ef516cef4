// MillStore: models and the records of calibration runs. The engine
// (engine/calibration_runs.h) fits, scores and decides; the store queues a
// run, claims it, records its outcome and, when the engine promotes,
// stores the model version, makes it active and writes the audit trail's
// row in one transaction; then the open campaign's rolls are re-predicted
// from their stored passes under the new model, before any reader of runs
// or versions sees the promotion (publish_mu_, mill_store_impl.h).
#include <mutex>
#include <string>
#include <utility>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {

StatusOr<ModelVersion> MillStoreImpl::ActiveModel() const {
  return *ActiveVersion();
}

std::vector<ModelVersion> MillStoreImpl::ListModels() const {
  std::lock_guard<std::mutex> published(publish_mu_);
  std::lock_guard<std::mutex> lock(read_mu_);
  StatusOr<std::vector<ModelVersion>> models = LoadModels(read_db_.get());
  if (!models.ok()) return {};
  return std::move(models).value();
}

StatusOr<int64_t> MillStoreImpl::EnqueueCalibration(const std::string& trigger,
                                                    const ModelChoice& model) {
  if (model.is_network()) {
    return InsertRun(trigger, model.Name(), 0, /*claim=*/false);
  }
  if (model.option < 1 || model.option > 3) {
    return Status::InvalidArgument("option: must be 1, 2 or 3, got " +
                                   std::to_string(model.option));
  }
  if (model.law != WearLaw::kWang && model.law != WearLaw::kNikitenko &&
      model.law != WearLaw::kCao) {
    return Status::InvalidArgument("model: must be wang, nikitenko or cao");
  }
  return InsertRun(trigger, model.Name(), model.option, /*claim=*/false);
}

StatusOr<int64_t> MillStoreImpl::InsertRun(const std::string& trigger,
                                           const std::string& model, int option,
                                           bool claim) {
  CalibrationRecord rec;
  rec.status = CalibrationStatus::kQueued;
  rec.trigger = trigger.empty() ? "api" : trigger;
  rec.model = model;
  rec.option = option;
  rec.queued_at = NowSeconds();
  int64_t id = 0;
  ROLLWEAR_RETURN_IF_ERROR(
      ClaimTask([&rec, &id, claim](Db* db) -> StatusOr<bool> {
        ROLLWEAR_ASSIGN_OR_RETURN(id, InsertCalibration(db, rec));
        if (!claim) return false;
        return internal::ClaimCalibration(db, id, rec.queued_at);
      }).status());
  return id;
}

StatusOr<bool> MillStoreImpl::ClaimTask(
    const std::function<StatusOr<bool>(Db*)>& claim) {
  bool claimed = false;
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&](Db* db) -> Status {
        ROLLWEAR_ASSIGN_OR_RETURN(claimed, claim(db));
        return Status::Ok();
      },
      [&](Db*) {
        if (!claimed) return;
        std::lock_guard<std::mutex> lock(mu_);
        counters_.measurements_since_last_calibration = 0;
      }));
  return claimed;
}

StatusOr<CalibrationRecord> MillStoreImpl::StartProposal(
    const std::string& trigger, const std::string& model, int option) {
  ROLLWEAR_ASSIGN_OR_RETURN(const int64_t id,
                            InsertRun(trigger, model, option, /*claim=*/true));
  return GetCalibration(id);
}

StatusOr<CalibrationRecord> MillStoreImpl::GetCalibration(int64_t id) const {
  std::lock_guard<std::mutex> published(publish_mu_);
  std::lock_guard<std::mutex> lock(read_mu_);
  ROLLWEAR_ASSIGN_OR_RETURN(std::optional<CalibrationRecord> rec,
                            LoadCalibration(read_db_.get(), id));
  if (!rec.has_value()) {
    return Status::NotFound("calibration " + std::to_string(id) +
                            ": unknown calibration");
  }
  return std::move(*rec);
}

std::vector<CalibrationRecord> MillStoreImpl::ListCalibrations(
    int limit) const {
  std::lock_guard<std::mutex> published(publish_mu_);
  std::lock_guard<std::mutex> lock(read_mu_);
  StatusOr<std::vector<CalibrationRecord>> recs =
      LoadCalibrations(read_db_.get(), limit);
  if (!recs.ok()) return {};
  return std::move(recs).value();
}

StatusOr<CalibrationRecord> MillStoreImpl::ClaimCalibration(int64_t id) {
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationRecord rec, GetCalibration(id));
  if (rec.status != CalibrationStatus::kQueued) {
    return Status::FailedPrecondition(
        "calibration " + std::to_string(id) + " is " +
        CalibrationStatusName(rec.status) + ", not queued");
  }
  rec.started_at = NowSeconds();
  ROLLWEAR_ASSIGN_OR_RETURN(
      const bool claimed, ClaimTask([&](Db* db) -> StatusOr<bool> {
        return internal::ClaimCalibration(db, id, rec.started_at);
      }));
  if (!claimed) {
    return Status::FailedPrecondition("calibration " + std::to_string(id) +
                                      " is no longer queued");
  }
  rec.status = CalibrationStatus::kRunning;
  return rec;
}

std::shared_ptr<const ModelVersion> MillStoreImpl::ActiveVersion() const {
  std::lock_guard<std::mutex> lock(mu_);
  return stored_model_;
}

Status MillStoreImpl::FinishCalibration(CalibrationRecord* run,
                                        std::optional<ModelVersion> promoted,
                                        int64_t replaced_version) {
  CalibrationRecord& rec = *run;
  if (promoted.has_value() && rec.status != CalibrationStatus::kDone) {
    return Status::InvalidArgument("calibration " + std::to_string(rec.id) +
                                   ": only a run that is done promotes");
  }
  std::lock_guard<std::mutex> promoting(promote_mu_);
  if (promoted.has_value()) {
    // The run was compared with `replaced_version`; a version made active
    // (or pinned) since then stays (ActivateModel holds promote_mu_ too).
    const std::shared_ptr<const ModelVersion> now = ActiveVersion();
    if (now->version != replaced_version) {
      promoted.reset();
      rec.message += "; not promoted: version " + std::to_string(now->version) +
                     " became active during the run (it was compared with "
                     "version " +
                     std::to_string(replaced_version) + ")";
    } else if (now->pinned) {
      promoted.reset();
      rec.message += "; not promoted: model pinned during the run (version " +
                     std::to_string(now->version) +
                     " was activated by hand; unpin it to let runs promote)";
    }
  }
  rec.promoted = promoted.has_value();
  if (!rec.promoted) {
    return RunTask([&rec](Db* db) { return UpdateCalibration(db, rec); },
                   nullptr);
  }
  auto version = std::make_shared<ModelVersion>(std::move(*promoted));
  version->created_at = rec.finished_at;
  version->model = rec.model;
  version->option = rec.option;
  version->active = true;
  version->pinned = false;
  version->gap_val_um = rec.gap_val_um;
  return RunTask(
      [&rec, replaced_version, version](Db* db) -> Status {
        ROLLWEAR_ASSIGN_OR_RETURN(const int64_t id,
                                  InsertActiveModel(db, *version, rec.id));
        version->version = id;
        rec.model_version = id;
        version->calibration_id = rec.id;
        version->trigger = rec.trigger;
        version->source = ModelSource(rec.trigger);
        version->gap_train_um = rec.gap_train_um;
        version->n_train = rec.n_train;
        version->n_val = rec.n_val;
        ROLLWEAR_RETURN_IF_ERROR(InsertPromotion(
            db, ModelPromotion{0, id, replaced_version, version->source,
                               rec.message, rec.finished_at, false}));
        return UpdateCalibration(db, rec);
      },
      [this, version](Db*) { InstallModel(version); });
}

}  // namespace rollwear::storage::internal
