// RollWearState: what the daemon keeps per mounted roll between coils (its
// predicted wear, the running gradient behind its interval, what scoped and
// extra-field terms read of the roll, the network's recurrence and the
// profile sums), a plain value. The functions that create and advance it
// are core/model/predictor.h's; the store keeps the states it commits
// (storage/store_types.h) without including them.
//
// Thread-safety: a plain value; callers serialise updates of one state.
#ifndef ROLLWEAR_CORE_MODEL_ROLL_WEAR_STATE_H_
#define ROLLWEAR_CORE_MODEL_ROLL_WEAR_STATE_H_

#include <optional>
#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"
#include "core/model/ann_model.h"
#include "core/model/barrel_profile.h"

namespace rollwear {

struct RollWearState {
  int position = -1;   // position level of the model (-1 unknown)
  int roll_type = -1;  // roll type level of the model (-1 unknown)
  double diameter_mm = 0;
  double hardness_hb = 0;
  double wear_um = 0;
  int coils = 0;
  double rolled_length_m = 0;
  std::vector<double> gradient;         // d(wear)/d(log k, a)
  UnixSeconds campaign_started_at = 0;  // for hours_since_mount
  // Where the roll runs and what it is, for scoped terms (TermScope):
  // parsed from the position label ("F6/top"; 0 / -1 when unparseable)
  // and the roll type label as mounted.
  int stand = 0;
  int roll_position = -1;
  std::string roll_type_label;
  std::string roll_id;         // the physical roll (a roll-effect term's level)
  ExtraFields mount_extra;     // the roll's extra fields (mounts.csv)
  ExtraFields campaign_extra;  // its campaign's (campaigns.csv)
  std::optional<AnnRollState> ann;  // set when the model is the ANN
  bool top_roll = true;  // from the position label (the shift convention)
  std::optional<ProfileStats> profile;  // set by TrackProfile
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_ROLL_WEAR_STATE_H_
