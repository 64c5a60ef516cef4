// The rules an input record must pass (docs/data-format.md, docs/api.md),
// written once for every way data comes in: the CSV reader
// (dataset_io.cc), import (storage/import_plan.cc), the store's writes
// (storage/validation.cc) and the HTTP request decoders
// (api/codec_decode.cc).
//
// Each function checks one record kind on already typed values and returns
// every broken rule, in the format's column order, as a RuleViolation:
// the field's name in the format (= CSV column = JSON member), the rule
// ("must be > 0") and, when the rule cites the offending value, that value
// in canonical form. The functions know nothing of where the record came
// from; the caller turns a violation into its own message:
//   CSV    "coils.csv:12:7 force_kn: must be > 0, got '-3.1'" (the text as
//          written, FileView)
//   store  "passes[1].force_kn: must be > 0, got -3" (RuleMessage)
//   API    field "passes[1].force_kn", message "passes[1].force_kn must be
//          > 0, got -3.0" (the JSON value as sent)
// Syntax stays with each reader: a missing or unparsable field, a stand or
// position name that does not parse, an empty CSV field.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_DATASET_INPUT_RULES_H_
#define ROLLWEAR_CORE_DATASET_INPUT_RULES_H_

#include <cstdint>
#include <functional>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"

namespace rollwear {

// Largest accepted seq (keeps seq in an int with room to spare).
inline constexpr int64_t kMaxSeq = 1'000'000'000;

enum class RuleKind {
  kRange,      // a value outside its range, an empty text or list
  kDuplicate,  // a stand or roll position twice in one record
};

struct RuleViolation {
  std::string field;  // "force_kn"; the list's name for an empty list
  // Index into the record's list (a coil's passes, a roll change's rolls)
  // of the element `field` belongs to; -1: the record itself.
  int element = -1;
  std::string rule;  // "must be > 0"
  // The message goes on ", got <value>": the field's value, canonical form
  // (shortest decimal, ISO 8601 UTC), for callers without the source text.
  bool cites_value = false;
  std::string value;
  RuleKind kind = RuleKind::kRange;
};
using RuleViolations = std::vector<RuleViolation>;

// rule + ", got " + value (when cited).
std::string RuleMessage(const RuleViolation& v);

// A roll position that exists, for a query that names one (GET
// /v1/wear/F6/top): InvalidArgument "stand: unknown stand 9 (want
// F1..F7)" or "position: want top or bottom".
Status CheckRollPosition(int stand, Position position);

// campaigns.csv, a campaign end: non-empty id; ended_at (when known) not
// before started_at.
RuleViolations CampaignRules(std::string_view campaign_id,
                             UnixSeconds started_at,
                             std::optional<UnixSeconds> ended_at);

// One mounted roll (a mounts.csv row without its campaign, an element of a
// roll change).
struct MountRecord {
  int stand = 0;
  Position position = Position::kTop;
  std::string_view roll_id;
  std::string_view roll_type;
  double diameter_mm = 0;
  double hardness_hb = 0;
};
// Stand F1..F7, position top/bottom, non-empty ids, diameter and hardness
// finite and > 0.
RuleViolations MountRules(const MountRecord& m);
// A roll change: non-empty campaign id, at least one roll, MountRules for
// each (element = index), each roll position once.
RuleViolations RollChangeRules(std::string_view campaign_id,
                               std::span<const MountRecord> rolls);

// The keys a coil's rows share: non-empty ids and grade, 1 <= seq <=
// kMaxSeq.
RuleViolations CoilKeyRules(std::string_view coil_id,
                            std::string_view campaign_id, int64_t seq,
                            std::string_view grade);
// One pass (a coils.csv row's measures): stand F1..F7; force, width,
// length, thicknesses and speed finite and > 0; exit < entry thickness;
// temperature and shift finite.
RuleViolations PassRules(const PassMeasures& p);
// A whole coil: CoilKeyRules, at least one pass, PassRules for each
// (element = index), each stand once. `pass_at(i)` is pass i of `num_passes`.
RuleViolations CoilRules(
    std::string_view coil_id, std::string_view campaign_id, int64_t seq,
    std::string_view grade, size_t num_passes,
    const std::function<const PassMeasures&(size_t)>& pass_at);
// The same on any contiguous range of PassMeasures or of a type derived
// from it (core's PassMeasures, storage's PassIn).
template <typename PassRange>
RuleViolations CoilRules(std::string_view coil_id, std::string_view campaign_id,
                         int64_t seq, std::string_view grade,
                         const PassRange& passes) {
  return CoilRules(coil_id, campaign_id, seq, grade, std::size(passes),
                   [&passes](size_t i) -> const PassMeasures& {
                     return std::data(passes)[i];
                   });
}

// One measurement: non-empty ids, stand F1..F7, position top/bottom, wear
// finite. (A finite wear that cannot be physical is not a rule break but a
// warning: core/dataset/data_quality.h.)
RuleViolations MeasurementRules(std::string_view campaign_id, int stand,
                                Position position, std::string_view roll_id,
                                double wear_center_um);

// One point of a grinder profile (profiles.csv): the same ids, x_mm and
// wear_um finite.
RuleViolations ProfilePointRules(std::string_view campaign_id, int stand,
                                 Position position, std::string_view roll_id,
                                 double x_mm, double wear_um);

// Consistency of one record with its campaign (data-format.md, bad input;
// api.md, 422). `mounted` has bit RollPositionSlot(stand, position) set for
// each roll position the campaign has a roll mounted at.

// A pass at `stand` (element = `pass` when >= 0, a coil's passes[i]): the
// campaign has a roll mounted at the stand (top or bottom). The rule names
// the roll positions the campaign does have, so that a stand named
// differently in two files shows ("no roll mounted at F7 in campaign C1;
// its rolls are at F5/top, F5/bottom").
RuleViolations PassMountRules(int stand, std::string_view campaign_id,
                              uint32_t mounted, int pass = -1);
// A measurement (or profile) taken at `measured_at`: its campaign has ended
// (`campaign_ended_at` is empty while it runs: field campaign_id) and
// measured_at is not before the end (field measured_at, value cited): the
// grinder measures a roll after it was taken out.
RuleViolations MeasurementTimeRules(
    std::string_view campaign_id, UnixSeconds measured_at,
    std::optional<UnixSeconds> campaign_ended_at);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_INPUT_RULES_H_
