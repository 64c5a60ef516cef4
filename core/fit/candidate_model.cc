#include "core/fit/candidate_model.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <utility>

#include "core/fit/identification.h"
#include "core/fit/study.h"
#include "core/fit/term_refit.h"
#include "core/model/aggregation.h"
#include "core/model/model_eval.h"

namespace rollwear {

StatusOr<CandidateInputs> PrepareCandidateInputs(const Dataset& data,
                                                 uint64_t split_seed) {
  CandidateInputs in{DatasetIndex(data), {}, {}};
  ROLLWEAR_ASSIGN_OR_RETURN(in.wang, Aggregate(data, in.index, WearLaw::kWang));
  in.split = SplitCampaigns(in.wang, 2.0 / 3.0, split_seed);
  return in;
}

namespace {

FitMetrics MetricsOn(const WearModel& m, const Dataset& data,
                     const DatasetIndex& index,
                     const std::vector<int>& campaigns) {
  return MetricsOfPredictions(PredictMeasured(m, data, index, campaigns));
}

// Fills the figures of `out` for its candidate and `active` on `split`
// (keeps a cost the fit already set).
void Score(const WearModel& active, const Dataset& data,
           const DatasetIndex& index, const CampaignSplit& split,
           CandidateEvaluation* out) {
  const WearModel& candidate = out->candidate;
  CandidateScore& s = out->score;
  const FitMetrics train = MetricsOn(candidate, data, index, split.train);
  const FitMetrics val = MetricsOn(candidate, data, index, split.validation);
  s.gap_train_um = train.gap_um;
  s.gap_val_um = val.gap_um;
  s.n_train = train.n;
  s.n_val = val.n;
  if (s.cost == 0) s.cost = train.cost;
  s.active_gap_val_um = MetricsOn(active, data, index, split.validation).gap_um;
  if (!candidate.is_ann()) s.coefficients = candidate.NamedCoefficients();
}

// Fits the candidate of `request` on split.train into `out` (model, summary
// and, for a calibration, its cost); an error says why there is none.
Status Fit(const Dataset& data, const CandidateInputs& inputs,
           const CandidateRequest& request, const WearModel& active,
           CandidateEvaluation* out) {
  const CampaignSplit& split = inputs.split;
  if (request.model.is_network()) {
    if (!request.train_network) {
      return Status::Internal("no trainer for the recurrent network");
    }
    ROLLWEAR_ASSIGN_OR_RETURN(FittedCandidate ann,
                              request.train_network(data, split.train));
    out->candidate = std::move(ann.model);
    out->summary = std::move(ann.summary);
    return Status::Ok();
  }
  const WearLaw law = request.model.law;
  if (!active.is_ann() && !active.terms.empty() && active.law == law &&
      request.model.option == 1) {
    ROLLWEAR_ASSIGN_OR_RETURN(
        out->candidate, RefitWithTerms(data, law, active.terms, split.train));
    out->summary = "option 1 with " + std::to_string(active.terms.size()) +
                   " adopted term(s) refitted";
    return Status::Ok();
  }
  std::optional<WearStatistics> other;  // the law's, unless Wang's
  if (law != WearLaw::kWang) {
    ROLLWEAR_ASSIGN_OR_RETURN(other, Aggregate(data, inputs.index, law));
  }
  const WearStatistics& stats = other.has_value() ? *other : inputs.wang;
  CalibrationOptions co;
  co.law = law;
  co.option = request.model.option;
  ROLLWEAR_ASSIGN_OR_RETURN(SplitCalibration run,
                            CalibrateOnSplit(stats, split, co));
  const CalibrationSummary& summary = run.result.summary;
  out->score.cost = summary.final_cost;
  out->summary = summary.BriefReport();
  if (!summary.usable) {
    return Status::NumericalFailure("calibration unusable: " +
                                    summary.BriefReport());
  }
  const Identification id =
      JudgeIdentification(run.result, run.train, run.validation);
  out->score.coefficients_identified = id.at_bound.empty() && id.large_error.empty();
  out->score.identification = id.Sentence();
  out->candidate = std::move(run.result.model);
  return Status::Ok();
}

}  // namespace

CandidateEvaluation FitCandidate(const Dataset& data,
                                 const CandidateRequest& request,
                                 const WearModel& active) {
  CandidateEvaluation out;
  try {
    StatusOr<CandidateInputs> inputs =
        PrepareCandidateInputs(data, request.split_seed);
    if (!inputs.ok()) {
      out.error = inputs.status();
      return out;
    }
    return FitCandidate(data, *inputs, request, active);
  } catch (const std::exception& e) {
    out.error = Status::Internal(std::string("calibration threw: ") + e.what());
  }
  return out;
}

CandidateEvaluation FitCandidate(const Dataset& data,
                                 const CandidateInputs& inputs,
                                 const CandidateRequest& request,
                                 const WearModel& active) {
  CandidateEvaluation out;
  try {
    out.error = Fit(data, inputs, request, active, &out);
    if (out.error.ok()) Score(active, data, inputs.index, inputs.split, &out);
  } catch (const std::exception& e) {
    out.error = Status::Internal(std::string("calibration threw: ") + e.what());
  }
  return out;
}

CandidateEvaluation ScoreCandidate(WearModel candidate, const WearModel& active,
                                   const Dataset& data, uint64_t split_seed) {
  CandidateEvaluation out;
  out.candidate = std::move(candidate);
  try {
    StatusOr<CandidateInputs> inputs = PrepareCandidateInputs(data, split_seed);
    if (!inputs.ok()) {
      out.error = inputs.status();
      return out;
    }
    Score(active, data, inputs->index, inputs->split, &out);
  } catch (const std::exception& e) {
    out.error = Status::Internal(std::string("proposal threw: ") + e.what());
  }
  return out;
}

PromotionDecision DecidePromotion(const CandidateScore& score,
                                  int64_t active_version) {
  PromotionDecision d;
  if (score.n_val <= 0) {
    d.reason = "; no measured validation campaign: nothing to compare on";
    return d;
  }
  if (!std::isfinite(score.gap_val_um)) {
    d.reason = "; the validation gap is not finite";
    return d;
  }
  d.comparable = true;
  d.promote = score.coefficients_identified &&
              (!std::isfinite(score.active_gap_val_um) ||
               score.gap_val_um <= score.active_gap_val_um);
  char gaps[160];
  std::snprintf(gaps, sizeof(gaps),
                "; validation gap %.2f um vs %.2f um for active model "
                "version %lld: %s",
                score.gap_val_um, score.active_gap_val_um,
                static_cast<long long>(active_version),
                d.promote ? "promoted" : "kept the active model");
  d.reason = gaps;
  if (!score.identification.empty() && score.identification != "identified") {
    d.reason += " (the candidate is " + score.identification + ")";
  }
  return d;
}

}  // namespace rollwear
