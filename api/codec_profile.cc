// Grinder profiles across the barrel: the body of POST /v1/profiles and
// its answer (codec.h).
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/codec.h"
#include "api/codec_json_util.h"
#include "api/codec_reader.h"
#include "api/json_scan.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::api {
namespace {

using codec_internal::Admissible;
using codec_internal::Dump;
using codec_internal::Json;
using codec_internal::ObjectReader;
using codec_internal::OutcomeName;

enum PointMember { kX, kWearUm };
constexpr std::string_view kPointMembers[] = {"x_mm", "wear_um"};
constexpr ObjectShape kPointShape{kPointMembers};
enum ProfileMember {
  kCampaignId,
  kStand,
  kPosition,
  kRollId,
  kMeasuredAt,
  kPoints
};
constexpr std::string_view kProfileMembers[] = {
    "campaign_id", "stand", "position", "roll_id", "measured_at", "points"};
constexpr ObjectShape kProfileShape{kProfileMembers, kPoints, &kPointShape,
                                    kMaxProfilePoints};

}  // namespace

bool DecodeProfile(std::string_view body, int max_depth,
                   storage::ProfileIn* out, ApiError* error) {
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kProfileShape, &scanned, error)) return false;
  ObjectReader r(scanned, kProfileShape, error);
  if (!r.Text(kCampaignId, &out->campaign_id) || !r.Stand(kStand, &out->stand) ||
      !r.PositionOf(kPosition, &out->position) ||
      !r.Text(kRollId, &out->roll_id) ||
      !r.Timestamp(kMeasuredAt, &out->measured_at) || !r.List(kPoints)) {
    return false;
  }
  out->points.reserve(scanned.elements.size());
  for (size_t i = 0; i < scanned.elements.size(); ++i) {
    if (!r.ElementIsObject(i)) return false;
    ObjectReader e(scanned.elements[i], kPointShape, error, "points",
                   static_cast<int>(i));
    storage::ProfilePointIn& p = out->points.emplace_back();
    if (!e.Number(kX, &p.x_mm) || !e.Number(kWearUm, &p.wear_um)) return false;
  }
  // The ids' rules, those of a profile point at a valid place (the points'
  // own rules are the store's: CheckProfileFields).
  return Admissible(r, {},
                    ProfilePointRules(out->campaign_id, out->stand,
                                      out->position, out->roll_id, 0, 0),
                    error);
}

std::string EncodeProfileAnswer(const storage::ProfileIn& in,
                                storage::WriteOutcome outcome) {
  return Dump(Json{{"campaign_id", in.campaign_id},
                   {"stand", StandName(in.stand)},
                   {"position", PositionName(in.position)},
                   {"roll_id", in.roll_id},
                   {"points", in.points.size()},
                   {"outcome", OutcomeName(outcome)}});
}

}  // namespace rollwear::api
