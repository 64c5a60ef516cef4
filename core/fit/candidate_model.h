// Candidate models: the choice, fitting and scoring of the model a
// calibration run proposes, and the rule that decides whether it replaces
// the active model. A run fits its candidate on the seeded 2/3 training
// campaigns of the data (SplitCampaigns, core/model/metrics.h), scores the
// candidate and the active model coil by coil (PredictMeasured,
// core/model/model_eval.h) on the same 1/3 validation campaigns, and
// promotes the candidate when its figures are usable, its fit is identified
// (core/fit/identification.h) and its validation gap (mean absolute
// difference between measured and predicted centre wear, um) is no worse
// than the active model's. The engine
// (engine/calibration_runs.h) runs it on the stored data; the store records
// the runs and promotes.
//
// Candidates (CandidateRequest::model, a ModelChoice):
//   the network          the recurrent network, trained by
//                        CandidateRequest::train_network (core/ann sits
//                        above core/fit, so the caller passes
//                        core/ann/ann_study.h's TrainServableAnn in)
//   a law, option 1, and the active model has adopted terms under that law
//                        option 1 and the terms refitted jointly
//                        (core/fit/term_refit.h): a nightly run keeps the
//                        physics a diagnosis added
//   otherwise            the classical calibration (CalibrateOnSplit,
//                        core/fit/study.h)
//   ScoreCandidate       a model fitted elsewhere (a diagnosis's adopted
//                        model), scored the same way
//
// Thread-safety: functions of their arguments only; safe to call
// concurrently (the network trainer must be too).
#ifndef ROLLWEAR_CORE_FIT_CANDIDATE_MODEL_H_
#define ROLLWEAR_CORE_FIT_CANDIDATE_MODEL_H_

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/ann_model.h"
#include "core/model/metrics.h"
#include "core/model/model_family.h"
#include "core/model/wear_model.h"

namespace rollwear {

// The figures of a candidate, and of the active model, on one split.
struct CandidateScore {
  // Training cost (Eq. 9, um^2): the calibration's final cost, else the
  // candidate's cost on the training campaigns.
  double cost = 0;
  double gap_train_um = 0;
  double gap_val_um = 0;
  double active_gap_val_um = 0;  // the active model, same campaigns
  int n_train = 0;               // measured rolls scored
  int n_val = 0;
  // The candidate's named coefficients (none for the network).
  std::vector<std::pair<std::string, double>> coefficients;
  // The classical calibration's identification verdict (identification.h):
  // whether its coefficients are identified (criteria 1 and 2: none at a
  // bound, none with relative s.e. > 100 %), and the verdict's sentence.
  // True, with an empty sentence, for candidates it does not judge (the
  // network, a refit with terms, a proposal).
  bool coefficients_identified = true;
  std::string identification;
};

// A scored candidate, or why there is none.
struct CandidateEvaluation {
  // Not OK when the candidate could not be fitted or is unusable; `score`
  // then holds at most the calibration's cost.
  Status error;
  WearModel candidate;
  std::string summary;  // what was fitted, in one line
  CandidateScore score;
};

// A model fitted on the training campaigns and what it is, in one line.
struct FittedCandidate {
  WearModel model;
  std::string summary;
};
using NetworkTrainer = std::function<StatusOr<FittedCandidate>(
    const Dataset& data, const std::vector<int>& train_campaigns)>;

// One run's data prepared once: indexed, aggregated for Wang (the split is
// drawn on that aggregation, and a Wang calibration fits it) and split with
// the seeded 2/3-1/3 split that calibration runs use (the one `rollwear
// calibrate` uses); a run's fit, scores and profile shape all read it.
struct CandidateInputs {
  DatasetIndex index;
  WearStatistics wang;
  CampaignSplit split;
};
StatusOr<CandidateInputs> PrepareCandidateInputs(const Dataset& data,
                                                 uint64_t split_seed);

struct CandidateRequest {
  ModelChoice model;  // a law and its K structure, or the network
  uint64_t split_seed = kDefaultSplitSeed;
  NetworkTrainer train_network;  // needed for the network only
};

// Chooses the candidate `request` names given the `active` model (table
// above), fits it on the training campaigns of `data` and scores it and
// `active` on the split. Never throws: an exception becomes `error`.
CandidateEvaluation FitCandidate(const Dataset& data,
                                 const CandidateRequest& request,
                                 const WearModel& active);
// The same on `inputs` (PrepareCandidateInputs of `data`), whose split is
// used (request.split_seed is not read).
CandidateEvaluation FitCandidate(const Dataset& data,
                                 const CandidateInputs& inputs,
                                 const CandidateRequest& request,
                                 const WearModel& active);

// Scores `candidate`, fitted elsewhere on `data`, and `active` on the
// validation campaigns of `data` under `split_seed` (the campaigns the
// candidate was not fitted on). Never throws.
CandidateEvaluation ScoreCandidate(WearModel candidate, const WearModel& active,
                                   const Dataset& data, uint64_t split_seed);

struct PromotionDecision {
  // The figures allow a comparison (a measured validation campaign and a
  // finite gap); when not, the run fails.
  bool comparable = false;
  bool promote = false;
  // Why, to append to the run's message: "; validation gap 10.31 um vs
  // 12.02 um for active model version 3: promoted".
  std::string reason;
};

// Promote when comparable, its coefficients identified and gap_val_um <=
// active_gap_val_um; an active model without a finite gap (never for a
// stored one) is beaten by any finite one. A candidate with a coefficient at
// a bound or a relative s.e. above 100 % is recorded with its figures and
// the verdict, and the active model is kept. The verdict's third criterion
// (a validation gap beyond the candidate's own noise model) does not stop
// a promotion: the gate already judges the held-out campaigns, against the
// active model, and on a young mill that criterion refuses candidates far
// better than the prior (docs/model.md, "Identification"); the reason then
// carries the verdict. `active_version` only names the active model in the
// reason.
PromotionDecision DecidePromotion(const CandidateScore& score,
                                  int64_t active_version);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_CANDIDATE_MODEL_H_
