// MillStore: models and calibration runs. A run exports the stored data,
// fits a candidate on the seeded 2/3 training campaigns, evaluates both the
// candidate and the active model coil by coil (core/model/model_eval.h) on the
// same 1/3 validation campaigns, and promotes the candidate (model row +
// active flag + run record in one transaction) when it is usable and no
// worse; then the open campaign's rolls are re-predicted from their stored
// passes under the new model.
//
// Candidates:
//   model "ann"                the recurrent network (core/ann/ann_study.h)
//   the active model's law, option 1, and the active model has adopted
//   terms                      option 1 and the terms refitted jointly
//                              (core/fit/term_refit.h): a nightly run keeps the
//                              physics a diagnosis added
//   otherwise                  the classical calibration (core/fit/study.h)
//   ProposeModel               a model fitted elsewhere (a diagnosis's
//                              adopted model), evaluated the same way
#include <cmath>
#include <cstdio>
#include <exception>
#include <utility>

#include "core/model/aggregation.h"
#include "core/ann/ann_study.h"
#include "core/model/metrics.h"
#include "core/model/model_eval.h"
#include "core/fit/study.h"
#include "core/fit/term_refit.h"
#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// What a run computed (before anything is written).
struct RunResult {
  Status error;  // the calibration could not run or is unusable
  WearModel candidate;
};

// The seeded training/validation split of the stored data (the same one
// `rollwear calibrate` uses).
StatusOr<CampaignSplit> SplitOf(const Dataset& data, const DatasetIndex& index,
                                uint64_t split_seed) {
  StatusOr<WearStatistics> stats = Aggregate(data, index, WearLaw::kWang);
  if (!stats.ok()) return stats.status();
  return SplitCampaigns(*stats, 2.0 / 3.0, split_seed);
}

FitMetrics MetricsOn(const WearModel& m, const Dataset& data,
                     const DatasetIndex& index, const std::vector<int>& campaigns) {
  return MetricsOfPredictions(PredictMeasured(m, data, index, campaigns));
}

// Fills the figures of `rec` for `candidate` and `active` on the split.
void Score(const WearModel& candidate, const WearModel& active, const Dataset& data,
           const DatasetIndex& index, const CampaignSplit& split,
           CalibrationRecord* rec) {
  const FitMetrics train = MetricsOn(candidate, data, index, split.train);
  const FitMetrics val = MetricsOn(candidate, data, index, split.validation);
  rec->gap_train_um = train.gap_um;
  rec->gap_val_um = val.gap_um;
  rec->n_train = train.n;
  rec->n_val = val.n;
  if (rec->cost == 0) rec->cost = train.cost;
  rec->active_gap_val_um = MetricsOn(active, data, index, split.validation).gap_um;
  if (!candidate.is_ann()) rec->coefficients = candidate.NamedCoefficients();
}

RunResult Calibrate(const Dataset& data, const std::string& model, int option,
                    uint64_t split_seed, const WearModel& active,
                    CalibrationRecord* rec) {
  RunResult out;
  const DatasetIndex index(data);
  StatusOr<CampaignSplit> split = SplitOf(data, index, split_seed);
  if (!split.ok()) {
    out.error = split.status();
    return out;
  }
  if (model == kAnnModelName) {
    StatusOr<WearModel> ann = TrainServableAnn(data, split->train, AnnTrainingOptions{});
    if (!ann.ok()) {
      out.error = ann.status();
      return out;
    }
    out.candidate = std::move(ann).value();
    rec->message = "recurrent network, ensemble of " +
                   std::to_string(AnnTrainingOptions{}.members) + " members";
    Score(out.candidate, active, data, index, *split, rec);
    return out;
  }
  WearLaw law = WearLaw::kWang;
  if (!ParseWearLaw(model, &law)) {
    out.error = Status::Internal("stored law '" + model + "' is unknown");
    return out;
  }
  if (!active.is_ann() && !active.terms.empty() && active.law == law && option == 1) {
    StatusOr<WearModel> refit = RefitWithTerms(data, law, active.terms, split->train);
    if (!refit.ok()) {
      out.error = refit.status();
      return out;
    }
    out.candidate = std::move(refit).value();
    rec->message = "option 1 with " + std::to_string(active.terms.size()) +
                   " adopted term(s) refitted";
    Score(out.candidate, active, data, index, *split, rec);
    return out;
  }
  StatusOr<WearStatistics> stats = Aggregate(data, index, law);
  if (!stats.ok()) {
    out.error = stats.status();
    return out;
  }
  CalibrationOptions co;
  co.law = law;
  co.option = option;
  StatusOr<SplitCalibration> run = CalibrateOnSplit(*stats, *split, co);
  if (!run.ok()) {
    out.error = run.status();
    return out;
  }
  const CalibrationSummary& summary = run->result.summary;
  rec->cost = summary.final_cost;
  rec->message = summary.BriefReport();
  if (!summary.usable) {
    out.error = Status::NumericalFailure("calibration unusable: " +
                                         summary.BriefReport());
    return out;
  }
  out.candidate = std::move(run->result.model);
  Score(out.candidate, active, data, index, *split, rec);
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
  return InsertRun(trigger, WearLawName(law), option, /*claim=*/false);
}

StatusOr<int64_t> MillStoreImpl::EnqueueAnnTraining(const std::string& trigger) {
  return InsertRun(trigger, kAnnModelName, 0, /*claim=*/false);
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
  bool claimed = false;
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&rec, &id, &claimed, claim](Db* db) -> Status {
        StatusOr<int64_t> row = InsertCalibration(db, rec);
        if (!row.ok()) return row.status();
        id = *row;
        if (claim) {
          StatusOr<bool> ok = ClaimCalibration(db, id, rec.queued_at);
          if (!ok.ok()) return ok.status();
          claimed = *ok;
        }
        return Status::Ok();
      },
      [&](Db*) {
        if (!claimed) return;
        std::lock_guard<std::mutex> lock(mu_);
        counters_.measurements_since_last_calibration = 0;
      }));
  return id;
}

StatusOr<CalibrationRecord> MillStoreImpl::ProposeModel(const std::string& trigger,
                                                        const std::string& model,
                                                        int option,
                                                        const WearModel& candidate,
                                                        const Dataset& data,
                                                        uint64_t split_seed) {
  std::lock_guard<std::mutex> runs(calibration_mu_);
  // Recorded as a run that is already running (claimed in the same
  // transaction), so the job worker never picks it up as a queued one.
  StatusOr<int64_t> id = InsertRun(trigger, model, option, /*claim=*/true);
  if (!id.ok()) return id.status();
  StatusOr<CalibrationRecord> claimed = GetCalibration(*id);
  if (!claimed.ok()) return claimed.status();
  CalibrationRecord rec = *claimed;
  std::shared_ptr<const ModelVersion> active;
  {
    std::lock_guard<std::mutex> lock(mu_);
    active = model_;
  }
  Status error;
  try {
    const DatasetIndex index(data);
    StatusOr<CampaignSplit> split = SplitOf(data, index, split_seed);
    if (!split.ok()) {
      error = split.status();
    } else {
      rec.message = "proposed by " + rec.trigger;
      Score(candidate, active->wear_model, data, index, *split, &rec);
    }
  } catch (const std::exception& e) {
    error = Status::Internal(std::string("proposal threw: ") + e.what());
  }
  rec.finished_at = NowSeconds();
  ROLLWEAR_RETURN_IF_ERROR(FinishRun(std::move(error), candidate, active, &rec));
  return rec;
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

  // 2. Calibrate (the store's locks are not held; this takes seconds). One
  //    run or proposal at a time, from reading the active model to the
  //    promotion.
  std::lock_guard<std::mutex> runs(calibration_mu_);
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
      result = Calibrate(*data, rec.model, rec.option, options_.split_seed,
                         active->wear_model, &rec);
    } catch (const std::exception& e) {
      result.error =
          Status::Internal(std::string("calibration threw: ") + e.what());
    }
  }
  rec.finished_at = NowSeconds();

  return FinishRun(std::move(result.error), std::move(result.candidate), active,
                   &rec);
}

Status MillStoreImpl::FinishRun(Status error, WearModel candidate,
                                const std::shared_ptr<const ModelVersion>& active,
                                CalibrationRecord* run) {
  CalibrationRecord& rec = *run;
  // 3. Record the run; promote when usable and no worse than the active
  //    model on the same validation campaigns.
  if (!error.ok()) {
    rec.status = CalibrationStatus::kFailed;
    rec.promoted = false;
    rec.message = error.message();
    return RunTask([&rec](Db* db) { return UpdateCalibration(db, rec); },
                   nullptr);
  }
  if (rec.n_val <= 0 || !std::isfinite(rec.gap_val_um)) {
    rec.status = CalibrationStatus::kFailed;
    rec.promoted = false;
    rec.message += rec.n_val <= 0 ? "; no measured validation campaign: nothing to compare on"
                                  : "; the validation gap is not finite";
    return RunTask([&rec](Db* db) { return UpdateCalibration(db, rec); }, nullptr);
  }
  rec.status = CalibrationStatus::kDone;
  // An active model without a finite gap (never happens for a stored
  // model; guarded all the same) is beaten by any finite one.
  rec.promoted = !std::isfinite(rec.active_gap_val_um) ||
                 rec.gap_val_um <= rec.active_gap_val_um;
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
  promoted->wear_model = std::move(candidate);
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
