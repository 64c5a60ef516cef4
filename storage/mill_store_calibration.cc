// MillStore: models and calibration runs. The store records each run,
// hands the fitting and scoring to core (core/fit/candidate_model.h: which
// candidate, fitted on the seeded 2/3 training campaigns, scored with the
// active model on the same 1/3 validation campaigns, promoted or not), and
// promotes the candidate (model row + active flag + run record in one
// transaction); then the open campaign's rolls are re-predicted from their
// stored passes under the new model, before any reader of runs or versions
// sees the promotion (publish_mu_, mill_store_impl.h).
#include <mutex>
#include <string>
#include <utility>

#include "core/ann/ann_study.h"
#include "core/fit/candidate_model.h"
#include "core/fit/profile_fit.h"
#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// The recurrent network of a run with model "ann" (core/fit sits below
// core/ann, so FitCandidate is handed the trainer).
StatusOr<FittedCandidate> TrainNetwork(
    const Dataset& data, const std::vector<int>& train_campaigns) {
  const AnnTrainingOptions options;
  ROLLWEAR_ASSIGN_OR_RETURN(WearModel ann,
                            TrainServableAnn(data, train_campaigns, options));
  return FittedCandidate{std::move(ann), "recurrent network, ensemble of " +
                                             std::to_string(options.members) +
                                             " members"};
}

// The profile shape of `model` (core/fit/profile_fit.h) fitted on the
// stored grinder profiles of the run's training campaigns (the same split),
// when there are any; why not is appended to *summary. The shape's
// covariance is the roll-clustered sandwich (a roll's points share its
// scatter), stored with the model version and read by the served interval
// (core/fit/profile_interval.h). K stays the centre fit's, which the
// promotion rule scored; the joint fit (profile_joint.h) would move it.
std::optional<ProfileFit> FitStoredProfileShape(const WearModel& model,
                                                const Dataset& data,
                                                uint64_t split_seed,
                                                std::string* summary) {
  if (data.profile_points.empty() || model.is_ann()) return std::nullopt;
  const DatasetIndex index(data);
  StatusOr<CampaignSplit> split = SplitOf(data, index, split_seed);
  StatusOr<ProfileFit> fit = split.ok()
                                 ? FitProfileShape(model, data, index, *split)
                                 : StatusOr<ProfileFit>(split.status());
  if (!fit.ok()) {
    *summary += "; no profile shape: " + fit.status().message();
    return std::nullopt;
  }
  *summary += "; profile shape on " + std::to_string(fit->train.n_points) +
              " points (roll-clustered s.e.)";
  return std::move(fit).value();
}

}  // namespace

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

StatusOr<int64_t> MillStoreImpl::EnqueueAnnTraining(
    const std::string& trigger) {
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
  ROLLWEAR_RETURN_IF_ERROR(
      ClaimTask([&rec, &id, claim](Db* db) -> StatusOr<bool> {
        ROLLWEAR_ASSIGN_OR_RETURN(id, InsertCalibration(db, rec));
        if (!claim) return false;
        return ClaimCalibration(db, id, rec.queued_at);
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

StatusOr<CalibrationRecord> MillStoreImpl::ProposeModel(
    const std::string& trigger, const std::string& model, int option,
    const WearModel& candidate, const Dataset& data, uint64_t split_seed) {
  std::lock_guard<std::mutex> runs(calibration_mu_);
  // Recorded as a run that is already running (claimed in the same
  // transaction), so the job worker never picks it up as a queued one.
  ROLLWEAR_ASSIGN_OR_RETURN(const int64_t id,
                            InsertRun(trigger, model, option, /*claim=*/true));
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationRecord rec, GetCalibration(id));
  const std::shared_ptr<const ModelVersion> active = ActiveVersion();
  CandidateEvaluation result =
      ScoreCandidate(candidate, active->wear_model, data, split_seed);
  result.summary = "proposed by " + rec.trigger;
  rec.finished_at = NowSeconds();
  ROLLWEAR_RETURN_IF_ERROR(FinishRun(std::move(result), active, &rec));
  return rec;
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

Status MillStoreImpl::RunCalibration(int64_t id) {
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationRecord rec, GetCalibration(id));
  if (rec.status != CalibrationStatus::kQueued) {
    return Status::FailedPrecondition(
        "calibration " + std::to_string(id) + " is " +
        CalibrationStatusName(rec.status) + ", not queued");
  }

  // 1. Claim the run; the measurements committed so far are the ones it
  //    sees ("since last calibration" restarts from here).
  rec.started_at = NowSeconds();
  ROLLWEAR_ASSIGN_OR_RETURN(const bool claimed,
                            ClaimTask([&](Db* db) -> StatusOr<bool> {
                              return ClaimCalibration(db, id, rec.started_at);
                            }));
  if (!claimed) {
    return Status::FailedPrecondition("calibration " + std::to_string(id) +
                                      " is no longer queued");
  }

  // 2. Fit and score the candidate (the store's locks are not held; this
  //    takes seconds). One run or proposal at a time, from reading the
  //    active model to the promotion.
  std::lock_guard<std::mutex> runs(calibration_mu_);
  const std::shared_ptr<const ModelVersion> active = ActiveVersion();
  CandidateEvaluation result;
  // Suspect measurements (storage/store_quality.h) are not fitted.
  StatusOr<FittingData> data = ReadFittingData();
  if (!data.ok()) {
    result.error = data.status();
  } else {
    CandidateRequest request;
    request.model = rec.model;
    request.option = rec.option;
    request.split_seed = options_.split_seed;
    request.train_network = TrainNetwork;
    result = FitCandidate(data->fit, request, active->wear_model);
  }
  std::optional<ProfileFit> profile;
  if (data.ok() && result.error.ok()) {
    profile = FitStoredProfileShape(result.candidate, data->fit,
                                    options_.split_seed, &result.summary);
  }
  rec.finished_at = NowSeconds();
  return FinishRun(std::move(result), active, &rec, std::move(profile));
}

std::shared_ptr<const ModelVersion> MillStoreImpl::ActiveVersion() const {
  std::lock_guard<std::mutex> lock(mu_);
  return model_;
}

Status MillStoreImpl::FinishRun(
    CandidateEvaluation result,
    const std::shared_ptr<const ModelVersion>& active, CalibrationRecord* run,
    std::optional<ProfileFit> profile) {
  CalibrationRecord& rec = *run;
  const CandidateScore& score = result.score;
  rec.cost = score.cost;
  rec.gap_train_um = score.gap_train_um;
  rec.gap_val_um = score.gap_val_um;
  rec.active_gap_val_um = score.active_gap_val_um;
  rec.n_train = score.n_train;
  rec.n_val = score.n_val;
  rec.coefficients = score.coefficients;
  // 3. Record the run; promote when core's rule says so.
  rec.promoted = false;
  if (!result.error.ok()) {
    rec.status = CalibrationStatus::kFailed;
    rec.message = result.error.message();
  } else {
    const PromotionDecision decision = DecidePromotion(score, active->version);
    rec.status = decision.comparable ? CalibrationStatus::kDone
                                     : CalibrationStatus::kFailed;
    rec.promoted = decision.promote;
    rec.message = result.summary + decision.reason;
    if (rec.promoted && active->pinned) {
      // Recorded, not promoted: a version activated by hand stays until
      // unpinned (MillStore::ActivateModel).
      rec.promoted = false;
      rec.message += "; not promoted: model pinned (version " +
                     std::to_string(active->version) +
                     " was activated by hand; unpin it to let runs promote)";
    }
  }
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
  promoted->profile = std::move(profile);
  return RunTask(
      [&rec, &active, promoted](Db* db) -> Status {
        ROLLWEAR_ASSIGN_OR_RETURN(const int64_t version,
                                  InsertActiveModel(db, *promoted, rec.id));
        promoted->version = version;
        rec.model_version = version;
        promoted->calibration_id = rec.id;
        promoted->trigger = rec.trigger;
        promoted->source = ModelSource(rec.trigger);
        promoted->gap_train_um = rec.gap_train_um;
        promoted->n_train = rec.n_train;
        promoted->n_val = rec.n_val;
        ROLLWEAR_RETURN_IF_ERROR(InsertPromotion(
            db, ModelPromotion{0, version, active->version, promoted->source,
                               rec.message, rec.finished_at, false}));
        return UpdateCalibration(db, rec);
      },
      [this, promoted](Db*) { InstallModel(promoted); });
}

}  // namespace rollwear::storage::internal
