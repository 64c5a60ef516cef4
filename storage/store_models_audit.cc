// MillStore: models under control. A stored version is made active by hand
// (ActivateModel: the active flag, the pin and one audit-trail row in one
// transaction, then the open campaign re-predicted under it through
// InstallModel, as a promotion does; activating with pin false unpins),
// and every promotion is read
// back from the audit trail (model_history, schema version 6). Calibration
// runs respect the pin (engine/calibration_runs.cc), and FinishCalibration
// (mill_store_calibration.cc) never promotes over a version activated
// during the run: both hold promote_mu_.
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {

StatusOr<ModelVersion> MillStoreImpl::GetModel(int64_t version) const {
  // Version 0 is the prior (the configured law, option and initial K),
  // never stored: the one answers name before the first promotion. Active
  // while nothing was promoted; else rebuilt for the positions seen.
  if (version == 0) {
    std::shared_ptr<const ModelVersion> active = ActiveVersion();
    if (active->version == 0) return *active;
    uint32_t seen = 0;
    {
      std::lock_guard<std::mutex> lock(mu_);
      seen = committed_.positions_seen;
    }
    ModelVersion prior = *MakePrior(seen);
    prior.active = false;
    return prior;
  }
  std::optional<ModelVersion> m;
  if (version > 0) {
    std::lock_guard<std::mutex> published(publish_mu_);
    std::lock_guard<std::mutex> lock(read_mu_);
    ROLLWEAR_ASSIGN_OR_RETURN(m, LoadModel(read_db_.get(), version));
  }
  if (!m.has_value()) {
    return Status::NotFound("model version " + std::to_string(version) +
                            ": unknown model version");
  }
  return std::move(*m);
}

StatusOr<ModelVersion> MillStoreImpl::ActivateModel(int64_t version,
                                                    const std::string& reason,
                                                    bool pin) {
  if (reason.find_first_not_of(" \t\r\n") == std::string::npos) {
    return Status::InvalidArgument(
        "reason: required, say why this version is activated");
  }
  // One activation or recorded promotion at a time, so each promotion
  // names the version it replaced and a run never promotes over a fresh
  // pin (FinishCalibration).
  std::lock_guard<std::mutex> promoting(promote_mu_);
  if (version <= 0) {
    return Status::NotFound("model version " + std::to_string(version) +
                            ": only a stored version can be activated "
                            "(version 0, the prior, is not stored)");
  }
  ROLLWEAR_ASSIGN_OR_RETURN(ModelVersion target, GetModel(version));
  const int64_t previous = ActiveVersion()->version;
  target.active = true;
  target.pinned = pin;
  auto next = std::make_shared<const ModelVersion>(target);
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&](Db* db) -> Status {
        ROLLWEAR_RETURN_IF_ERROR(SetActiveModel(db, version, pin));
        return InsertPromotion(
            db, ModelPromotion{0, version, previous, "manual", reason,
                               NowSeconds(), pin});
      },
      [this, next](Db*) { InstallModel(next); }));
  return target;
}

StatusOr<std::vector<ModelPromotion>> MillStoreImpl::ModelHistory(
    int limit) const {
  std::lock_guard<std::mutex> published(publish_mu_);
  std::lock_guard<std::mutex> lock(read_mu_);
  return LoadPromotions(read_db_.get(), limit);
}

}  // namespace rollwear::storage::internal
