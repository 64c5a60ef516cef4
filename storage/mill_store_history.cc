// MillStore::RecentWear: the wear history behind the daemon's dashboard.
// Replays the open campaign's stored passes (recording each roll's wear
// after every coil) and the last ended, measured campaigns under the active
// model, on the read connection. The replay is the one that restores the
// live state on start (same passes, same order, same model), so the open
// campaign's last points equal the engine's wear answer
// (engine::MountedRolls::Wear). A measured roll also gets what the
// grinder is expected to read (the model's measurement terms added,
// WearPredictor::ReadingOffset), the number validation compares with the
// measurement.
#include <algorithm>
#include <memory>
#include <mutex>
#include <vector>

#include "storage/extra_json.h"
#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// Replays `rec` under `model` into `out` (ReplayCampaignCoils: the replay
// that restores the live state); with `track`, also every roll's wear after
// each of its passes.
Status ReplayInto(Db* db, const WearPredictor& predictor,
                  const CampaignRec& rec, const WearModel& model, bool track,
                  CampaignWearHistory* out) {
  std::array<int, kNumRollPositionSlots> index{};
  index.fill(-1);
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    const auto& m = rec.mounts[slot];
    if (!m.has_value()) continue;
    RollWearHistory h;
    h.stand = m->stand;
    h.position = m->position;
    h.roll_id = m->roll_id;
    if (rec.measurements[slot].has_value()) {
      h.measured_um = rec.measurements[slot]->wear_center_um;
      h.measured_suspect = rec.measurements[slot]->suspect;
    }
    index[slot] = static_cast<int>(out->rolls.size());
    out->rolls.push_back(std::move(h));
  }
  CoilVisitor record;
  if (track) {
    record = [&](const ReplayedCoil& coil) {
      for (const CoilWearEntry& e : coil.entries) {
        RollWearHistory& h = out->rolls[index[e.slot]];
        h.rolled_length_m.push_back(e.rolled_length_m);
        h.predicted_wear_um.push_back(e.total_um);
      }
      return Status::Ok();
    };
  }
  ROLLWEAR_ASSIGN_OR_RETURN(
      const RollStates states,
      ReplayCampaignCoils(db, predictor, rec, model, record));
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (index[slot] < 0) continue;
    RollWearHistory& h = out->rolls[index[slot]];
    h.final_predicted_um = states[slot]->wear_um;
    h.expected_reading_um = h.final_predicted_um;
    h.expected_reading_um += StoredReadingOffset(predictor, model, rec, slot);
  }
  return Status::Ok();
}

bool HasMeasurement(const CampaignRec& rec) {
  return std::any_of(rec.measurements.begin(), rec.measurements.end(),
                     [](const auto& m) { return m.has_value(); });
}

}  // namespace

double StoredReadingOffset(const WearPredictor& predictor,
                           const WearModel& model, const CampaignRec& rec,
                           int slot) {
  const auto& measured = rec.measurements[slot];
  const auto& m = rec.mounts[slot];
  if (!measured.has_value() || !m.has_value() || !rec.ended_at.has_value())
    return 0;
  ReadingContext reading;
  reading.stand = m->stand;
  reading.position = static_cast<int>(m->position);
  reading.roll_type = m->roll_type;
  reading.measured_at = measured->measured_at;
  reading.ended_at = rec.ended_at;
  reading.extra = &measured->extra;
  return predictor.ReadingOffset(model, reading);
}

StatusOr<std::vector<CampaignWearHistory>> MillStoreImpl::RecentWear(
    int ended_campaigns) const {
  std::shared_ptr<const ModelVersion> model;
  std::vector<CampaignRec> recs;  // open first, then newest ended
  {
    std::lock_guard<std::mutex> lock(mu_);
    model = model_;
    if (!committed_.open_campaign.empty()) {
      auto it = committed_.campaigns.find(committed_.open_campaign);
      if (it != committed_.campaigns.end()) recs.push_back(it->second);
    }
    std::vector<const CampaignRec*> ended;
    for (const auto& [id, rec] : committed_.campaigns) {
      if (rec.ended_at.has_value() && HasMeasurement(rec)) {
        ended.push_back(&rec);
      }
    }
    std::sort(ended.begin(), ended.end(),
              [](const CampaignRec* a, const CampaignRec* b) {
                return a->started_at != b->started_at
                           ? a->started_at > b->started_at
                           : a->id > b->id;
              });
    const size_t n = std::min(
        ended.size(), static_cast<size_t>(std::max(0, ended_campaigns)));
    for (size_t i = 0; i < n; ++i) recs.push_back(*ended[i]);
  }
  std::vector<CampaignWearHistory> out;
  std::lock_guard<std::mutex> lock(read_mu_);
  for (const CampaignRec& rec : recs) {
    CampaignWearHistory h;
    h.campaign_id = rec.id;
    h.started_at = rec.started_at;
    h.open = !rec.ended_at.has_value();
    ROLLWEAR_RETURN_IF_ERROR(ReplayInto(read_db_.get(), predictor_, rec,
                                        model->wear_model, h.open, &h));
    out.push_back(std::move(h));
  }
  return out;
}

}  // namespace rollwear::storage::internal
