// MillStore: the served model's per-roll wear factors, re-estimated from
// the stored readings (WearPredictor::WithRollFactors, the engine's:
// core/model/roll_factor_update.h). The version as
// stored (stored_model_) keeps the factors its calibration fitted; the
// served one (model_) has every measured roll's level re-estimated from
// all of that roll's plausible stored readings, given K and the other
// terms, when the model is installed (start, promotion, activation) and
// for the measured rolls whenever a measurement or an import commits. A
// reading's prediction is the replay of its campaign's stored passes under
// the served model (the prediction the daemon served), divided by the
// factor that replay used.
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

// Whether slot `slot` of `rec` holds a plausible reading of one of `rolls`
// (of any roll when empty) on an ended campaign.
bool WantedReading(const CampaignRec& rec, int slot,
                   const std::set<std::string>& rolls) {
  const auto& m = rec.mounts[slot];
  const auto& reading = rec.measurements[slot];
  return m.has_value() && reading.has_value() && reading->suspect.empty() &&
         rec.ended_at.has_value() &&
         (rolls.empty() || rolls.count(m->roll_id) > 0);
}

}  // namespace

std::vector<CampaignRec> MeasuredCampaignsOf(
    const Catalog& catalog, const std::set<std::string>& rolls) {
  std::vector<CampaignRec> out;
  for (const auto& [id, rec] : catalog.campaigns) {
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      if (WantedReading(rec, slot, rolls)) {
        out.push_back(rec);
        break;
      }
    }
  }
  return out;
}

StatusOr<std::shared_ptr<const ModelVersion>> WithRollReadings(
    Db* db, const WearPredictor& predictor,
    const std::vector<CampaignRec>& campaigns,
    std::shared_ptr<const ModelVersion> model,
    const std::set<std::string>& rolls) {
  const WearModel& wm = model->wear_model;
  const ModelTerm* term = predictor.UpdatableRollTerm(wm);
  if (term == nullptr) return model;
  std::map<std::string, std::vector<RollFactorReading>> readings;
  for (const CampaignRec& rec : campaigns) {
    ROLLWEAR_ASSIGN_OR_RETURN(const RollStates states,
                              ReplayCampaign(db, predictor, rec, wm));
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      if (!WantedReading(rec, slot, rolls) || !states[slot].has_value()) {
        continue;
      }
      const MountedRollIn& mount = *rec.mounts[slot];
      // Outside the term's scope the roll's factor does not act.
      if (!term->scope.CoversRoll(mount.stand, static_cast<int>(mount.position),
                                  mount.roll_type)) {
        continue;
      }
      RollFactorReading r;
      r.base_um = states[slot]->wear_um /
                  std::exp(predictor.RollLogFactor(*term, mount.roll_id));
      r.offset_um = StoredReadingOffset(predictor, wm, rec, slot);
      r.measured_um = rec.measurements[slot]->wear_center_um;
      readings[mount.roll_id].push_back(r);
    }
  }
  if (readings.empty()) return model;
  auto served = std::make_shared<ModelVersion>(*model);
  served->wear_model = predictor.WithRollFactors(wm, readings);
  return std::shared_ptr<const ModelVersion>(std::move(served));
}

}  // namespace rollwear::storage::internal
