#include "engine/mounted_rolls.h"

#include <array>
#include <optional>
#include <string>
#include <utility>

#include "core/dataset/input_rules.h"
#include "core/model/predictor.h"
#include "core/model/profile_interval.h"
#include "core/model/remaining_life.h"

namespace rollwear::engine {

using storage::MountedRoll;
using storage::MountedState;
using storage::RollSlots;

namespace {

// The store's moment `*mounted` and the slot of (stand, position), once the
// position exists (CheckRollPosition) and holds a roll (NotFound "no roll
// mounted at F6/top").
StatusOr<int> MountedSlot(const storage::MillStore& store, int stand,
                          Position position, MountedState* mounted) {
  ROLLWEAR_RETURN_IF_ERROR(CheckRollPosition(stand, position));
  const int slot = RollPositionSlot(stand, position);
  *mounted = store.Mounted();
  if (!(*mounted->rolls)[slot]) {
    return Status::NotFound("no roll mounted at " +
                            RollPositionName(stand, position));
  }
  return slot;
}

}  // namespace

PositionWear PositionWearOf(const MountedState& mounted, int slot) {
  const MountedRoll& roll = *(*mounted.rolls)[slot];
  const WearModel& model = mounted.model->wear_model;
  PositionWear w;
  w.stand = SlotStand(slot);
  w.position = SlotPosition(slot);
  w.roll_id = roll.mount.roll_id;
  w.roll_type = roll.mount.roll_type;
  w.campaign_id = mounted.campaign_id;
  w.coils = roll.state.coils;
  w.rolled_length_m = roll.state.rolled_length_m;
  w.predicted_wear_um = roll.state.wear_um;
  const auto [lo, hi] = WearInterval(model, roll.state);
  w.interval_lo_um = lo;
  w.interval_hi_um = hi;
  w.wear_limit_um = mounted.wear_limit_um[slot];
  if (w.wear_limit_um) {
    w.remaining = PredictRemainingLife(model, roll.state, *w.wear_limit_um);
  }
  return w;
}

WearSnapshot MountedRolls::Wear() const {
  const MountedState mounted = store_->Mounted();
  WearSnapshot snap;
  snap.model_version = mounted.model->version;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if ((*mounted.rolls)[slot]) {
      snap.positions.push_back(PositionWearOf(mounted, slot));
    }
  }
  return snap;
}

StatusOr<PositionWear> MountedRolls::WearAt(int stand, Position position,
                                            int64_t* model_version) const {
  MountedState mounted;
  ROLLWEAR_ASSIGN_OR_RETURN(const int slot,
                            MountedSlot(*store_, stand, position, &mounted));
  if (model_version != nullptr) *model_version = mounted.model->version;
  return PositionWearOf(mounted, slot);
}

StatusOr<ProfileWear> MountedRolls::WearProfileAt(int stand,
                                                  Position position) const {
  // The centre and the sums of one moment (a coil commits both at once).
  MountedState mounted;
  ROLLWEAR_ASSIGN_OR_RETURN(const int slot,
                            MountedSlot(*store_, stand, position, &mounted));
  return ProfileWearOf(mounted, slot);
}

StatusOr<ProfileWear> ProfileWearOf(const MountedState& mounted, int slot) {
  const std::optional<ProfileStats>& stats =
      (*mounted.rolls)[slot]->state.profile;
  if (!stats.has_value()) {
    return Status::Internal(
        "no profile state at " +
        RollPositionName(SlotStand(slot), SlotPosition(slot)));
  }
  ProfileWear out;
  out.centre = PositionWearOf(mounted, slot);
  out.model_version = mounted.model->version;
  out.shape = mounted.model->profile;
  out.profile =
      PredictProfile(*stats, out.shape.has_value() ? &*out.shape : nullptr,
                     out.centre.predicted_wear_um,
                     {out.centre.interval_lo_um, out.centre.interval_hi_um});
  return out;
}

StatusOr<Forecast> MountedRolls::ForecastCoils(
    const std::vector<storage::CoilIn>& coils) const {
  ROLLWEAR_ASSIGN_OR_RETURN(const storage::PlannedSchedule plan,
                            store_->PlanCoils(coils));
  const MountedState& start = plan.start;
  RollSlots rolls = *start.rolls;  // the copies the schedule runs through
  Forecast out;
  out.model_version = start.model->version;
  std::array<int, kNumRollPositionSlots> index{};
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (!rolls[slot]) continue;
    index[slot] = static_cast<int>(out.positions.size());
    ForecastPosition p;
    p.stand = SlotStand(slot);
    p.position = SlotPosition(slot);
    p.roll_id = rolls[slot]->mount.roll_id;
    p.campaign_id = start.campaign_id;
    p.wear_limit_um = start.wear_limit_um[slot];
    p.predicted_wear_um.reserve(plan.coils.size());
    p.interval_um.reserve(plan.coils.size());
    out.positions.push_back(std::move(p));
  }
  const WearModel& wear_model = start.model->wear_model;
  for (size_t i = 0; i < plan.coils.size(); ++i) {
    const storage::PlannedCoil& coil = plan.coils[i];
    out.coil_ids.push_back(coil.coil_id);
    for (const storage::PlannedPass& pass : coil.passes) {
      for (Position pos : {Position::kTop, Position::kBottom}) {
        auto& roll = rolls[RollPositionSlot(pass.stand, pos)];
        if (roll) AddPass(wear_model, pass.input, &roll->state);
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

}  // namespace rollwear::engine
