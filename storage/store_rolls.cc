// MillStore: rolls across campaigns (GET /v1/rolls, GET /v1/rolls/{id}).
// A roll's mounts and measurements come from the published catalog (every
// campaign with its mounts and measurements is held in memory); its
// predicted wear at the end of each ended mount is a replay of that
// campaign's stored passes under the active model (the replay that restores
// the live state on start), and the running mount's is the live state. The
// inventory's rolled lengths are the catalog's per campaign and stand
// (CampaignRec::length_m, summed as coils commit), added up per roll over
// its mounts: the inventory reads nothing from SQLite.
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// The catalog's campaigns in the order they were started.
std::vector<const CampaignRec*> ByStart(const Catalog& catalog) {
  std::vector<const CampaignRec*> out;
  out.reserve(catalog.campaigns.size());
  for (const auto& [id, rec] : catalog.campaigns) out.push_back(&rec);
  std::sort(
      out.begin(), out.end(), [](const CampaignRec* a, const CampaignRec* b) {
        return a->started_at != b->started_at ? a->started_at < b->started_at
                                              : a->id < b->id;
      });
  return out;
}

}  // namespace

StatusOr<RollLife> MillStoreImpl::GetRollLife(
    const std::string& roll_id) const {
  RollLife life;
  life.roll_id = roll_id;
  std::vector<CampaignRec> recs;  // the campaigns it was mounted in
  std::vector<int> slots;
  std::shared_ptr<const ModelVersion> model;
  std::optional<RollWearState> live;  // its state, when mounted now
  {
    std::lock_guard<std::mutex> lock(mu_);
    model = model_;
    for (const CampaignRec* rec : ByStart(committed_)) {
      for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
        const auto& m = rec->mounts[slot];
        if (!m.has_value() || m->roll_id != roll_id) continue;
        recs.push_back(*rec);
        slots.push_back(slot);
        if (rec->id == committed_.open_campaign && (*rolls_)[slot]) {
          live = (*rolls_)[slot]->state;
        }
      }
    }
  }
  if (recs.empty()) {
    return Status::NotFound("roll '" + roll_id + "': unknown roll");
  }
  life.model_version = model->version;
  life.wear_factor = RollWearFactorOf(model->wear_model.terms, roll_id);
  for (size_t i = 0; i < recs.size(); ++i) {
    const CampaignRec& rec = recs[i];
    const int slot = slots[i];
    const MountedRollIn& m = *rec.mounts[slot];
    RollMountLife mount;
    mount.campaign_id = rec.id;
    mount.stand = m.stand;
    mount.position = m.position;
    mount.started_at = rec.started_at;
    mount.ended_at = rec.ended_at;
    mount.diameter_mm = m.diameter_mm;
    mount.hardness_hb = m.hardness_hb;
    std::optional<RollWearState> state;
    if (!rec.ended_at.has_value() && live.has_value()) {
      state = live;
    } else {
      std::lock_guard<std::mutex> lock(read_mu_);
      ROLLWEAR_ASSIGN_OR_RETURN(
          RollStates states,
          ReplayCampaign(read_db_.get(), predictor_, rec, model->wear_model));
      state = states[slot];
    }
    if (state.has_value()) {
      mount.coils = state->coils;
      mount.rolled_length_m = state->rolled_length_m;
      mount.predicted_wear_um = state->wear_um;
    }
    if (rec.measurements[slot].has_value()) {
      mount.measured_um = rec.measurements[slot]->wear_center_um;
      mount.expected_reading_um =
          mount.predicted_wear_um +
          StoredReadingOffset(predictor_, model->wear_model, rec, slot);
      mount.measured_suspect = rec.measurements[slot]->suspect;
    }
    life.roll_type = m.roll_type;
    life.mounts.push_back(std::move(mount));
  }
  return life;
}

StatusOr<std::vector<RollSummary>> MillStoreImpl::RollInventory() const {
  std::map<std::string, RollSummary> rolls;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const CampaignRec* rec : ByStart(committed_)) {
      const bool open = rec->id == committed_.open_campaign;
      for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
        const auto& m = rec->mounts[slot];
        if (!m.has_value()) continue;
        RollSummary& r = rolls[m->roll_id];
        r.roll_id = m->roll_id;
        r.roll_type = m->roll_type;
        r.last_diameter_mm = m->diameter_mm;
        ++r.campaigns;
        r.total_rolled_m += rec->length_m[m->stand];
        r.mounted = open;
        if (open) {
          r.stand = m->stand;
          r.position = m->position;
          r.campaign_id = rec->id;
        }
        const auto& measured = rec->measurements[slot];
        if (measured.has_value()) {
          r.last_measured_um = measured->wear_center_um;
          r.last_measured_suspect = measured->suspect;
        }
      }
    }
  }
  std::vector<RollSummary> out;
  out.reserve(rolls.size());
  for (auto& [id, r] : rolls) out.push_back(std::move(r));
  return out;
}

}  // namespace rollwear::storage::internal
