// MillStore::ForecastCoils: a planned schedule run through copies of the
// open campaign's roll states (the predictor of the writer's PredictBatch,
// on the same canonical passes), storing nothing.
//
// Thread-safety: as MillStoreImpl; the live state is copied under mu_ and
// the schedule predicted without the lock.
#include <string>
#include <unordered_map>
#include <utility>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"
#include "storage/validation.h"

namespace rollwear::storage::internal {
namespace {

// "coils[i]." before a store message that names a field of the coil.
Status InCoil(size_t i, const Status& s) {
  return Status(s.code(), "coils[" + std::to_string(i) + "]." + s.message());
}

}  // namespace

StatusOr<Forecast> MillStoreImpl::ForecastCoils(
    const std::vector<CoilIn>& coils) const {
  std::vector<StoredCoil> schedule;
  schedule.reserve(coils.size());
  for (size_t i = 0; i < coils.size(); ++i) {
    const Status fields = CheckCoilFields(coils[i]);
    if (!fields.ok()) return InCoil(i, fields);
    schedule.push_back(CanonicalCoil(coils[i]));
  }
  Forecast out;
  std::shared_ptr<const ModelVersion> model;
  std::array<std::optional<LiveRoll>, kNumRollPositionSlots> rolls;
  std::array<std::optional<double>, kNumRollPositionSlots> limits;
  std::string campaign_id;
  {
    std::lock_guard<std::mutex> lock(mu_);
    const std::string& open = committed_.open_campaign;
    // A planned coil is one not yet rolled: posting a stored coil again
    // adds nothing (200 unchanged), so forecasting it would not equal what
    // posting gives; a coil planned twice neither.
    std::unordered_map<std::string, size_t> first;
    for (size_t i = 0; i < coils.size(); ++i) {
      const std::string& id = coils[i].coil_id;
      if (auto [it, fresh] = first.emplace(id, i); !fresh) {
        return InCoil(i, Status::InvalidArgument(
                             "coil_id: " + id + " is planned twice (first as "
                             "coils[" + std::to_string(it->second) + "])"));
      }
      bool stored = spec_.pending_coils.count(id) > 0;
      if (!stored && committed_coil_ids_.MayContain(id)) {
        ROLLWEAR_ASSIGN_OR_RETURN(std::optional<StoredCoil> found,
                                  LookupCoil(lookup_db_.get(), id));
        stored = found.has_value();
      }
      if (stored) {
        return InCoil(i, Status::FailedPrecondition(
                             "coil_id: coil " + id +
                             " is already stored: a forecast plans coils not "
                             "yet rolled (give planned coils new ids)"));
      }
    }
    for (size_t i = 0; i < coils.size(); ++i) {
      if (coils[i].campaign_id != open) {
        return InCoil(i, Status::FailedPrecondition(
                             "campaign_id: coil is for campaign " +
                             coils[i].campaign_id + "; the running campaign " +
                             (open.empty() ? "is none" : "is " + open)));
      }
      bool unchanged = false;
      const Status admit =
          AdmitCoil(committed_, coils[i], schedule[i], std::nullopt, &unchanged,
                    /*check_seq=*/false);
      if (!admit.ok()) return InCoil(i, admit);
    }
    model = model_;
    rolls = rolls_;
    campaign_id = open;
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      if (rolls[slot]) limits[slot] = LimitLocked(slot).limit_um;
    }
  }
  out.model_version = model->version;
  std::array<int, kNumRollPositionSlots> index{};
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (!rolls[slot]) continue;
    index[slot] = static_cast<int>(out.positions.size());
    ForecastPosition p;
    p.stand = SlotStand(slot);
    p.position = SlotPosition(slot);
    p.roll_id = rolls[slot]->mount.roll_id;
    p.campaign_id = campaign_id;
    p.wear_limit_um = limits[slot];
    p.predicted_wear_um.reserve(schedule.size());
    p.interval_um.reserve(schedule.size());
    out.positions.push_back(std::move(p));
  }
  const WearModel& wear_model = model->wear_model;
  for (size_t i = 0; i < schedule.size(); ++i) {
    const StoredCoil& coil = schedule[i];
    out.coil_ids.push_back(coil.coil_id);
    for (const StoredPass& pass : coil.passes) {
      const PassInput in = ToPassInput(coil.grade, pass);
      for (Position pos : {Position::kTop, Position::kBottom}) {
        auto& roll = rolls[RollPositionSlot(pass.stand, pos)];
        if (roll) AddPass(wear_model, in, &roll->state);
      }
    }
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      if (!rolls[slot]) continue;
      ForecastPosition& p = out.positions[index[slot]];
      const RollWearState& state = rolls[slot]->state;
      p.predicted_wear_um.push_back(state.wear_um);
      p.interval_um.push_back(WearInterval(wear_model, state));
      if (p.first_crossing < 0 && p.wear_limit_um &&
          state.wear_um >= *p.wear_limit_um) {
        p.first_crossing = static_cast<int>(i);
      }
    }
  }
  return out;
}

}  // namespace rollwear::storage::internal
