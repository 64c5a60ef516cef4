#include "engine/calibration_runs.h"

#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "core/ann/ann_study.h"
#include "core/dataset/timestamp.h"
#include "core/fit/profile_fit.h"

namespace rollwear::engine {
namespace {

using storage::CalibrationRecord;
using storage::CalibrationStatus;
using storage::ModelVersion;

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
// stored grinder profiles of the run's training campaigns (`inputs`: the
// run's index and split), when there are any; why not is appended to
// *summary. The shape's
// covariance is the roll-clustered sandwich (a roll's points share its
// scatter), stored with the model version and read by the served interval
// (core/model/profile_interval.h). K stays the centre fit's, which the
// promotion rule scored; the joint fit (profile_joint.h) would move it.
std::optional<ProfileFit> FitStoredProfileShape(const WearModel& model,
                                                const Dataset& data,
                                                const CandidateInputs& inputs,
                                                std::string* summary) {
  if (data.profile_points.empty() || model.is_ann()) return std::nullopt;
  StatusOr<ProfileFit> fit =
      FitProfileShape(model, data, inputs.index, inputs.split);
  if (!fit.ok()) {
    *summary += "; no profile shape: " + fit.status().message();
    return std::nullopt;
  }
  *summary += "; profile shape on " + std::to_string(fit->train.n_points) +
              " points (roll-clustered s.e.)";
  return std::move(fit).value();
}

// PrepareCandidateInputs, whose exceptions (an allocation failure) become
// the run's error as FitCandidate's do.
StatusOr<CandidateInputs> PrepareCandidate(const Dataset& data,
                                           uint64_t split_seed) {
  try {
    return PrepareCandidateInputs(data, split_seed);
  } catch (const std::exception& e) {
    return Status::Internal(std::string("calibration threw: ") + e.what());
  }
}

}  // namespace

CalibrationRuns::CalibrationRuns(storage::MillStore* store,
                                 CalibrationRunOptions options)
    : store_(store), options_(options) {}

Status CalibrationRuns::Run(int64_t id) {
  // 1. Claim the run; the measurements committed so far are the ones it
  //    sees ("since last calibration" restarts from here).
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationRecord rec,
                            store_->ClaimCalibration(id));

  // 2. Fit and score the candidate (no lock of the store is held; this
  //    takes seconds). One run or proposal at a time, from reading the
  //    active model to the promotion.
  std::lock_guard<std::mutex> runs(runs_mu_);
  StatusOr<ModelVersion> read = store_->ActiveModel();
  if (!read.ok()) return FailClaimed(read.status(), &rec);
  const ModelVersion& active = *read;
  CandidateEvaluation result;
  std::optional<ProfileFit> profile;
  // The stored run names its model; it is read as a typed choice once.
  // Suspect measurements (storage/store_quality.h) are not fitted. The data
  // are indexed, aggregated and split once for the fit, the scores and the
  // profile shape.
  const StatusOr<ModelChoice> choice = ParseModelChoice(rec.model, rec.option);
  StatusOr<storage::FittingData> data =
      choice.ok() ? store_->ReadFittingData()
                  : StatusOr<storage::FittingData>(choice.status());
  StatusOr<CandidateInputs> inputs =
      data.ok() ? PrepareCandidate(data->fit, options_.split_seed)
                : StatusOr<CandidateInputs>(data.status());
  if (!inputs.ok()) {
    result.error = inputs.status();
  } else {
    CandidateRequest request;
    request.model = *choice;
    request.train_network = TrainNetwork;
    result = FitCandidate(data->fit, *inputs, request, active.wear_model);
    if (result.error.ok()) {
      profile = FitStoredProfileShape(result.candidate, data->fit, *inputs,
                                      &result.summary);
    }
  }
  rec.finished_at = NowSeconds();
  return Finish(std::move(result), active, &rec, std::move(profile));
}

StatusOr<CalibrationRecord> CalibrationRuns::Propose(
    const std::string& trigger, const std::string& model, int option,
    const WearModel& candidate, const Dataset& data, uint64_t split_seed) {
  std::lock_guard<std::mutex> runs(runs_mu_);
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationRecord rec,
                            store_->StartProposal(trigger, model, option));
  StatusOr<ModelVersion> read = store_->ActiveModel();
  if (!read.ok()) {
    ROLLWEAR_RETURN_IF_ERROR(FailClaimed(read.status(), &rec));
    return rec;
  }
  const ModelVersion& active = *read;
  CandidateEvaluation result =
      ScoreCandidate(candidate, active.wear_model, data, split_seed);
  result.summary = "proposed by " + rec.trigger;
  rec.finished_at = NowSeconds();
  ROLLWEAR_RETURN_IF_ERROR(Finish(std::move(result), active, &rec));
  return rec;
}

Status CalibrationRuns::FailClaimed(const Status& why, CalibrationRecord* run) {
  run->status = CalibrationStatus::kFailed;
  run->message = "cannot read the active model: " + why.message();
  run->finished_at = NowSeconds();
  return store_->FinishCalibration(run, std::nullopt, 0);
}

Status CalibrationRuns::Finish(CandidateEvaluation result,
                               const ModelVersion& active,
                               CalibrationRecord* run,
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
  bool promote = false;
  if (!result.error.ok()) {
    rec.status = CalibrationStatus::kFailed;
    rec.message = result.error.message();
  } else {
    const PromotionDecision decision = DecidePromotion(score, active.version);
    rec.status = decision.comparable ? CalibrationStatus::kDone
                                     : CalibrationStatus::kFailed;
    promote = decision.promote;
    rec.message = result.summary + decision.reason;
    if (promote && active.pinned) {
      // Recorded, not promoted: a version activated by hand stays until
      // unpinned (MillStore::ActivateModel).
      promote = false;
      rec.message += "; not promoted: model pinned (version " +
                     std::to_string(active.version) +
                     " was activated by hand; unpin it to let runs promote)";
    }
  }
  std::optional<ModelVersion> promoted;
  if (promote) {
    promoted.emplace();
    promoted->wear_model = std::move(result.candidate);
    promoted->profile = std::move(profile);
  }
  return store_->FinishCalibration(run, std::move(promoted), active.version);
}

}  // namespace rollwear::engine
