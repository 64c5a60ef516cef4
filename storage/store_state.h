// Internal to storage (included only by storage/*.cc and its tests): the
// in-memory catalog that MillStore validates writes against, and the
// canonical forms of stored rows used to decide idempotent repeats.
//
// The catalog holds every campaign with its mounts and measurements (a few
// hundred a year), the open campaign and the seq numbers its coils use.
// Coils themselves stay in the database; only coils queued but not yet
// committed are held here (pending_coils) so that a duplicate posted
// concurrently is seen before its twin commits.
//
// Thread-safety: plain values; MillStore guards them with its mutex.
#ifndef ROLLWEAR_STORAGE_STORE_STATE_H_
#define ROLLWEAR_STORAGE_STORE_STATE_H_

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/dataset/pass_input.h"
#include "core/model/roll_wear_state.h"
#include "storage/store_types.h"

namespace rollwear::storage::internal {

// One pass as stored (a row of passes): the pass, its coil's time and the
// extra fields of its row (the coil's and the pass's own, merged).
struct StoredPass : PassMeasures {
  UnixSeconds rolled_at = 0;
  ExtraFields extra;
  bool operator==(const StoredPass&) const = default;
};

// A coil with its passes ordered by stand: the canonical content that
// idempotent repeats are compared on (numbers compared exactly, extra
// fields included: a repeat that adds, drops or changes one differs).
struct StoredCoil {
  std::string coil_id;
  std::string campaign_id;
  int seq = 0;
  std::string grade;
  std::vector<StoredPass> passes;
  bool operator==(const StoredCoil&) const = default;
};

StoredCoil CanonicalCoil(const CoilIn& in);

// What a coil added to one roll position: the wear of its pass there and
// the roll's predicted total right after it (a CoilOutcome::Added without
// the labels, which follow from the slot and the campaign's mounts), and
// the length the roll has rolled by then (a replay's, for the wear history;
// not part of a stored coil's answer, EncodeCoilWear).
struct CoilWearEntry {
  int slot = 0;
  double wear_um = 0;
  double total_um = 0;
  double rolled_length_m = 0;
};

// What the predictor (WearPredictor::AddPass) needs of a stored pass of a
// coil of `grade`.
PassInput ToPassInput(const std::string& grade, const StoredPass& p);

bool SameMount(const MountedRollIn& a, const MountedRollIn& b);
bool SameMeasurement(const MeasurementIn& a, const MeasurementIn& b);

struct CampaignRec {
  std::string id;
  UnixSeconds started_at = 0;
  std::optional<UnixSeconds> ended_at;  // empty while open
  ExtraFields extra;                    // the campaign's extra fields
  std::array<std::optional<MountedRollIn>, kNumRollPositionSlots> mounts;
  std::array<std::optional<MeasurementIn>, kNumRollPositionSlots> measurements;
  // What each stand (index 1..kMaxStand) rolled in this campaign: Wang's
  // load sum force / width * length and the rolled length of its passes,
  // added as coils are applied. A new reading is judged on these
  // (JudgeLastReading, core/dataset/data_quality.h) without re-reading the
  // passes.
  std::array<double, kMaxStand + 1> load{};
  std::array<double, kMaxStand + 1> length_m{};
};

struct Catalog {
  std::unordered_map<std::string, CampaignRec> campaigns;
  std::string open_campaign;  // empty when no campaign is open
  // seq -> coil_id of the open campaign's coils (coils are only accepted
  // for the open campaign, so seq clashes are checked here).
  std::unordered_map<int, std::string> open_seqs;
  // Coils queued but not committed (speculative catalog only).
  std::unordered_map<std::string, StoredCoil> pending_coils;
  uint32_t positions_seen = 0;  // bit per roll position slot ever mounted
  // Campaign ids in the order of their rows (the order they were stored).
  std::vector<std::string> order;
};

// Adds `coil`'s passes to its campaign's per-stand load and length (a coil
// of a campaign not in `c` adds nothing).
void AddExposure(const StoredCoil& coil, Catalog* c);

// Position labels ("F6/top") of the slots in `mask`, ascending slot order.
std::vector<std::string> PositionLabels(uint32_t mask);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_STORE_STATE_H_
