// MillStore::RecentProfiles: the measured against predicted profiles of the
// daemon's dashboard. The last ended campaigns with a stored grinder
// profile are replayed under the active model with their rolls' profile
// sums tracked (ReplayCampaign, the replay that restores the live state on
// start), and each stored point gets the model's profile there: the sums
// read with the model's shape (g = 1 without one), interpolated between
// slices at the point (WearPredictor::ProfileAt, the engine's), as the
// profile gap reads a point.
#include <algorithm>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// Ids of the `limit` most recently started ended campaigns that have a
// stored profile, newest first.
StatusOr<std::vector<std::string>> CampaignsWithProfiles(Db* db, int limit) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement * st,
                            db->Cached(kCampaignsWithProfilesSql));
  const ResetOnExit reset(st);
  st->BindInt(1, limit);
  std::vector<std::string> out;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(
      st, [&](const Statement& row) { out.push_back(row.ColumnText(0)); }));
  return out;
}

// The stored profiles of `rec` with the prediction of `model` (its replayed
// roll states `states`) at their points, appended to `out`.
Status PredictStoredProfiles(Db* db, const WearPredictor& predictor,
                             const CampaignRec& rec, const ModelVersion& model,
                             std::vector<MeasuredProfile>* out) {
  std::vector<std::pair<int, ProfileIn>> stored;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (!rec.mounts[slot].has_value()) continue;
    ProfileIn key;
    key.campaign_id = rec.id;
    key.stand = SlotStand(slot);
    key.position = SlotPosition(slot);
    ROLLWEAR_ASSIGN_OR_RETURN(std::optional<ProfileIn> profile,
                              LookupProfile(db, key));
    if (profile.has_value()) stored.emplace_back(slot, std::move(*profile));
  }
  if (stored.empty()) return Status::Ok();
  ROLLWEAR_ASSIGN_OR_RETURN(const RollStates states,
                            ReplayCampaign(db, predictor, rec, model.wear_model,
                                           /*track_profiles=*/true));
  const ProfileShape shape =
      model.profile.has_value() ? model.profile->shape : ProfileShape();
  for (const auto& [slot, in] : stored) {
    const auto& state = states[slot];
    // No profile state (the recurrent network's model): nothing to compare.
    if (!state.has_value() || !state->profile.has_value()) continue;
    MeasuredProfile m;
    m.campaign_id = rec.id;
    m.stand = in.stand;
    m.position = in.position;
    m.roll_id = in.roll_id;
    m.calibrated = model.profile.has_value();
    for (const ProfilePointIn& p : in.points) {
      m.x_mm.push_back(p.x_mm);
      m.measured_um.push_back(p.wear_um);
    }
    m.predicted_um = predictor.ProfileAt(*state, shape, m.x_mm);
    out->push_back(std::move(m));
  }
  return Status::Ok();
}

}  // namespace

StatusOr<std::vector<MeasuredProfile>> MillStoreImpl::RecentProfiles(
    int ended_campaigns) const {
  std::vector<MeasuredProfile> out;
  if (ended_campaigns <= 0) return out;
  // The locks one at a time, as RecentWear takes them (never nested).
  std::vector<std::string> ids;
  {
    std::lock_guard<std::mutex> read_lock(read_mu_);
    ROLLWEAR_ASSIGN_OR_RETURN(
        ids, CampaignsWithProfiles(read_db_.get(), ended_campaigns));
  }
  std::shared_ptr<const ModelVersion> model;
  std::vector<CampaignRec> recs;
  {
    std::lock_guard<std::mutex> lock(mu_);
    model = model_;
    for (const std::string& id : ids) {
      auto it = committed_.campaigns.find(id);
      if (it != committed_.campaigns.end()) recs.push_back(it->second);
    }
  }
  std::lock_guard<std::mutex> read_lock(read_mu_);
  for (const CampaignRec& rec : recs) {
    ROLLWEAR_RETURN_IF_ERROR(
        PredictStoredProfiles(read_db_.get(), predictor_, rec, *model, &out));
  }
  return out;
}

}  // namespace rollwear::storage::internal
