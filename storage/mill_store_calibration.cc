// MillStore: models and calibration runs. A run exports the stored data,
// calibrates on the seeded 2/3 training campaigns, evaluates both the
// candidate and the active model on the same 1/3 validation campaigns, and
// promotes the candidate (model row + active flag + run record in one
// transaction) when it is usable and no worse; then the open campaign's
// rolls are re-predicted from their stored passes under the new model.
#include <cstdio>
#include <exception>
#include <utility>

#include "core/aggregation.h"
#include "core/metrics.h"
#include "core/study.h"
#include "storage/mill_store_impl.h"
#include "storage/model_levels.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// What a run computed (before anything is written).
struct RunResult {
  Status error;  // the calibration could not run or is unusable
  WearModel candidate;
};

// Validation gap of `active` on the validation campaigns of `split`,
// computed on statistics of the active model's own law.
StatusOr<double> ActiveGap(const WearModel& active, const Dataset& data,
                           const DatasetIndex& index,
                           const WearStatistics& stats,
                           const CampaignSplit& split) {
  const WearStatistics* s = &stats;
  WearStatistics own;
  if (active.law != stats.law) {
    StatusOr<WearStatistics> agg = Aggregate(data, index, active.law);
    if (!agg.ok()) return agg.status();
    own = std::move(agg).value();
    s = &own;
  }
  StatusOr<WearModel> over =
      ModelOverLevels(active, s->positions, s->roll_types, s->grades);
  if (!over.ok()) return over.status();
  return Evaluate(*over, *s, s->MeasuredObservations(split.validation)).gap_um;
}

RunResult Calibrate(const Dataset& data, WearLaw law, int option,
                    uint64_t split_seed, const WearModel& active,
                    CalibrationRecord* rec) {
  RunResult out;
  const DatasetIndex index(data);
  StatusOr<WearStatistics> stats = Aggregate(data, index, law);
  if (!stats.ok()) {
    out.error = stats.status();
    return out;
  }
  const CampaignSplit split = SplitCampaigns(*stats, 2.0 / 3.0, split_seed);
  CalibrationOptions co;
  co.law = law;
  co.option = option;
  StatusOr<SplitCalibration> run = CalibrateOnSplit(*stats, split, co);
  if (!run.ok()) {
    out.error = run.status();
    return out;
  }
  const CalibrationSummary& summary = run->result.summary;
  rec->coefficients = run->result.model.NamedCoefficients();
  rec->cost = summary.final_cost;
  rec->gap_train_um = run->train.gap_um;
  rec->gap_val_um = run->validation.gap_um;
  rec->n_train = run->train.n;
  rec->n_val = run->validation.n;
  rec->message = summary.BriefReport();
  if (!summary.usable) {
    out.error = Status::NumericalFailure("calibration unusable: " +
                                         summary.BriefReport());
    return out;
  }
  StatusOr<double> active_gap = ActiveGap(active, data, index, *stats, split);
  if (!active_gap.ok()) {
    out.error = active_gap.status();
    return out;
  }
  rec->active_gap_val_um = *active_gap;
  out.candidate = std::move(run->result.model);
  return out;
}

}  // namespace

StatusOr<ModelVersion> MillStoreImpl::ActiveModel() const {
  std::lock_guard<std::mutex> lock(mu_);
  return *model_;
}

std::vector<ModelVersion> MillStoreImpl::ListModels() const {
  std::lock_guard<std::mutex> lock(read_mu_);
  StatusOr<std::vector<ModelVersion>> models = LoadModels(read_db_.get());
  if (!models.ok()) return {};
  return std::move(models).value();
}

StatusOr<int64_t> MillStoreImpl::EnqueueCalibration(const std::string& trigger,
                                                    WearLaw law, int option) {
  if (option < 1 || option > 3) {
    return Status::InvalidArgument("option: must be 1, 2 or 3, got " +
                                   std::to_string(option));
  }
  if (law != WearLaw::kWang && law != WearLaw::kNikitenko &&
      law != WearLaw::kCao) {
    return Status::InvalidArgument("model: must be wang, nikitenko or cao");
  }
  CalibrationRecord rec;
  rec.status = CalibrationStatus::kQueued;
  rec.trigger = trigger.empty() ? "api" : trigger;
  rec.model = WearLawName(law);
  rec.option = option;
  rec.queued_at = NowSeconds();
  int64_t id = 0;
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&rec, &id](Db* db) -> Status {
        StatusOr<int64_t> row = InsertCalibration(db, rec);
        if (!row.ok()) return row.status();
        id = *row;
        return Status::Ok();
      },
      nullptr));
  return id;
}

StatusOr<CalibrationRecord> MillStoreImpl::GetCalibration(int64_t id) const {
  std::lock_guard<std::mutex> lock(read_mu_);
  StatusOr<std::optional<CalibrationRecord>> rec =
      LoadCalibration(read_db_.get(), id);
  if (!rec.ok()) return rec.status();
  if (!rec->has_value()) {
    return Status::NotFound("calibration " + std::to_string(id) +
                            ": unknown calibration");
  }
  return std::move(**rec);
}

std::vector<CalibrationRecord> MillStoreImpl::ListCalibrations(
    int limit) const {
  std::lock_guard<std::mutex> lock(read_mu_);
  StatusOr<std::vector<CalibrationRecord>> recs =
      LoadCalibrations(read_db_.get(), limit);
  if (!recs.ok()) return {};
  return std::move(recs).value();
}

Status MillStoreImpl::RunCalibration(int64_t id) {
  StatusOr<CalibrationRecord> queued = GetCalibration(id);
  if (!queued.ok()) return queued.status();
  if (queued->status != CalibrationStatus::kQueued) {
    return Status::FailedPrecondition(
        "calibration " + std::to_string(id) + " is " +
        CalibrationStatusName(queued->status) + ", not queued");
  }
  CalibrationRecord rec = *queued;
  WearLaw law = WearLaw::kWang;
  if (!ParseWearLaw(rec.model, &law)) {
    return Status::Internal("calibration " + std::to_string(id) +
                            ": stored law '" + rec.model + "' is unknown");
  }

  // 1. Claim the run; the measurements committed so far are the ones it
  //    sees ("since last calibration" restarts from here).
  rec.started_at = NowSeconds();
  bool claimed = false;
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&](Db* db) -> Status {
        StatusOr<bool> ok = ClaimCalibration(db, id, rec.started_at);
        if (!ok.ok()) return ok.status();
        claimed = *ok;
        return Status::Ok();
      },
      [&](Db*) {
        if (!claimed) return;
        std::lock_guard<std::mutex> lock(mu_);
        counters_.measurements_since_last_calibration = 0;
      }));
  if (!claimed) {
    return Status::FailedPrecondition("calibration " + std::to_string(id) +
                                      " is no longer queued");
  }

  // 2. Calibrate (no lock held; this takes seconds).
  std::shared_ptr<const ModelVersion> active;
  {
    std::lock_guard<std::mutex> lock(mu_);
    active = model_;
  }
  RunResult result;
  StatusOr<Dataset> data = ExportDataset();
  if (!data.ok()) {
    result.error = data.status();
  } else {
    try {
      result = Calibrate(*data, law, rec.option, options_.split_seed,
                         active->wear_model, &rec);
    } catch (const std::exception& e) {
      result.error =
          Status::Internal(std::string("calibration threw: ") + e.what());
    }
  }
  rec.finished_at = NowSeconds();

  // 3. Record the run; promote when usable and no worse than the active
  //    model on the same validation campaigns.
  if (!result.error.ok()) {
    rec.status = CalibrationStatus::kFailed;
    rec.promoted = false;
    rec.message = result.error.message();
    return RunTask([&rec](Db* db) { return UpdateCalibration(db, rec); },
                   nullptr);
  }
  rec.status = CalibrationStatus::kDone;
  rec.promoted = rec.gap_val_um <= rec.active_gap_val_um;
  char gaps[160];
  std::snprintf(gaps, sizeof(gaps),
                "; validation gap %.2f um vs %.2f um for active model "
                "version %lld: %s",
                rec.gap_val_um, rec.active_gap_val_um,
                static_cast<long long>(active->version),
                rec.promoted ? "promoted" : "kept the active model");
  rec.message += gaps;
  if (!rec.promoted) {
    return RunTask([&rec](Db* db) { return UpdateCalibration(db, rec); },
                   nullptr);
  }
  auto promoted = std::make_shared<ModelVersion>();
  promoted->created_at = rec.finished_at;
  promoted->model = rec.model;
  promoted->option = rec.option;
  promoted->active = true;
  promoted->gap_val_um = rec.gap_val_um;
  promoted->wear_model = std::move(result.candidate);
  return RunTask(
      [&rec, promoted](Db* db) -> Status {
        StatusOr<int64_t> version = InsertActiveModel(db, *promoted, rec.id);
        if (!version.ok()) return version.status();
        promoted->version = *version;
        rec.model_version = *version;
        return UpdateCalibration(db, rec);
      },
      [this, promoted](Db*) { InstallModel(promoted); });
}

}  // namespace rollwear::storage::internal
