// CalibrationRuns: the engine's calibration work on a store. A queued run
// (MillStore::EnqueueCalibration: a law and option, or the network) is claimed,
// core chooses and fits the candidate on the stored data with the seeded
// 2/3-1/3 split (core/fit/candidate_model.h; the recurrent network for model
// "ann", core/ann/ann_study.h), scores it and the active model on the same
// validation campaigns, fits the profile shape on the stored grinder
// profiles (core/fit/profile_fit.h), and the store records the outcome and
// promotes atomically when core's rule says so (DecidePromotion) and the
// active version is not pinned. A model fitted elsewhere (a diagnosis's
// adoption) is proposed the same way and scored on the data and split it
// was fitted on.
//
// Layers: service -> api -> engine -> storage -> core. The store keeps
// SQLite, the schema, the writer and the records; it includes no fitting
// or network header.
//
// Thread-safety: Run and Propose are thread-safe and serialised: one run
// or proposal at a time, from reading the active model to promoting, so
// each is compared with the model it replaces. One CalibrationRuns per
// store (the daemon's scheduler and diagnosis jobs share it): two would
// still never promote over each other's result (the store promotes only
// over the version a run was compared with), but the second run would be
// recorded "not promoted: version N became active during the run".
#ifndef ROLLWEAR_ENGINE_CALIBRATION_RUNS_H_
#define ROLLWEAR_ENGINE_CALIBRATION_RUNS_H_

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/fit/candidate_model.h"
#include "core/model/profile_calibration.h"
#include "core/model/wear_model.h"
#include "storage/mill_store.h"

namespace rollwear::engine {

struct CalibrationRunOptions {
  // Seed of the 2/3-1/3 campaign split of calibration runs (the one
  // `rollwear calibrate` uses by default).
  uint64_t split_seed = kDefaultSplitSeed;
};

class CalibrationRuns {
 public:
  // `store` must outlive this object.
  explicit CalibrationRuns(storage::MillStore* store,
                           CalibrationRunOptions options = {});

  CalibrationRuns(const CalibrationRuns&) = delete;
  CalibrationRuns& operator=(const CalibrationRuns&) = delete;

  // Executes the queued run `id` (called by the calibration worker,
  // service/jobs/scheduler.h). Returns OK once the run is recorded, done or
  // failed (see MillStore::GetCalibration); NotFound for an unknown id,
  // FailedPrecondition when the run is not queued, the database error when
  // it could not be recorded.
  Status Run(int64_t id);

  // Records and runs at once a run for `candidate`, fitted elsewhere (a
  // diagnosis's adopted model: option 1 plus terms) on `data`: it and the
  // active model are scored coil by coil on the validation campaigns of
  // `data` under `split_seed` (the campaigns the candidate was not fitted
  // on), and it is promoted when no worse. Returns the run's record (done
  // or failed); an error only when the run could not be recorded.
  StatusOr<storage::CalibrationRecord> Propose(
      const std::string& trigger, const std::string& model, int option,
      const WearModel& candidate, const Dataset& data, uint64_t split_seed);

 private:
  // Copies `result`'s figures into *run, decides against `active`, and has
  // the store record the run and promote the candidate (with `profile`,
  // its profile shape) when decided so.
  Status Finish(CandidateEvaluation result, const storage::ModelVersion& active,
                storage::CalibrationRecord* run,
                std::optional<ProfileFit> profile = std::nullopt);
  // Records a claimed run failed with `why` (no model is read or promoted),
  // so that no run stays "running".
  Status FailClaimed(const Status& why, storage::CalibrationRecord* run);

  storage::MillStore* const store_;
  const CalibrationRunOptions options_;
  std::mutex runs_mu_;
};

}  // namespace rollwear::engine

#endif  // ROLLWEAR_ENGINE_CALIBRATION_RUNS_H_
