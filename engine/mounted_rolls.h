// MountedRolls: the engine's answers about the rolls mounted now. The store
// keeps the mounted rolls' predicted states as its writer commits them
// (MillStore::Mounted); the engine reads them with core's model: each
// roll's wear interval (core/model/predictor.h, WearInterval), its
// remaining life to the wear limit in force
// (core/model/remaining_life.h), its profile across the barrel with the
// model's shape (core/model/profile_interval.h), and a planned schedule run
// through copies of the states (the writer's predictor on the same
// canonical passes, MillStore::PlanCoils).
//
// Layers: service -> api -> engine -> storage -> core.
//
// Thread-safety: thread-safe; each answer reads one consistent moment of
// the store (one Mounted() or PlanCoils()) and computes without a lock.
#ifndef ROLLWEAR_ENGINE_MOUNTED_ROLLS_H_
#define ROLLWEAR_ENGINE_MOUNTED_ROLLS_H_

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "engine/wear_answers.h"
#include "storage/mill_store.h"

namespace rollwear::engine {

class MountedRolls {
 public:
  // `store` must outlive this object.
  explicit MountedRolls(const storage::MillStore* store) : store_(store) {}

  // The store's mounted rolls at this moment (MillStore::Mounted), for a
  // caller that reads several answers of one moment (PositionWearOf,
  // ProfileWearOf).
  storage::MountedState Mounted() const { return store_->Mounted(); }
  // The rolls of the open campaign (none once it has ended and no roll
  // change has followed), by stand, top first, with the served model's
  // version.
  WearSnapshot Wear() const;
  // One roll position: InvalidArgument "stand: ..." / "position: ..." for
  // one that does not exist (CheckRollPosition), NotFound "no roll mounted
  // at F6/top". `model_version` (may be null) receives the version of the
  // served model the answer was read with (the same moment).
  StatusOr<PositionWear> WearAt(int stand, Position position,
                                int64_t* model_version = nullptr) const;
  // The predicted profile across the barrel of the roll at (stand,
  // position), read from its profile sums with the served model's profile
  // shape, or the default g = 1 when it has none; errors as WearAt.
  StatusOr<ProfileWear> WearProfileAt(int stand, Position position) const;
  // The predicted wear of every mounted roll after each coil of a planned
  // schedule, with intervals and the first coil at which each roll's wear
  // limit is reached. Stores nothing; the coils are checked as
  // MillStore::PlanCoils says (its errors). The same coils posted with
  // AddCoil then leave Wear() at the last values.
  StatusOr<Forecast> ForecastCoils(
      const std::vector<storage::CoilIn>& coils) const;

 private:
  const storage::MillStore* const store_;
};

// The answer for the roll at `slot` of `mounted` (which must hold one).
PositionWear PositionWearOf(const storage::MountedState& mounted, int slot);
// Its predicted profile across the barrel (MountedRolls::WearProfileAt);
// Internal "no profile state at F6/top" when its state tracks none.
StatusOr<ProfileWear> ProfileWearOf(const storage::MountedState& mounted,
                                    int slot);

}  // namespace rollwear::engine

#endif  // ROLLWEAR_ENGINE_MOUNTED_ROLLS_H_
