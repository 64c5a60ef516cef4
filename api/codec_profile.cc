// Grinder profiles across the barrel: the body of POST /v1/profiles and
// its answer (codec.h).
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/codec.h"
#include "api/codec_json_util.h"
#include "api/codec_reader.h"
#include "api/json_scan.h"
#include "api/json_writer.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::api {
namespace {

using codec_internal::Admissible;
using codec_internal::Dump;
using codec_internal::Json;
using codec_internal::ObjectReader;
using codec_internal::OutcomeName;

enum PointMember { kPointX, kPointWearUm };
constexpr std::string_view kPointMembers[] = {"x_mm", "wear_um"};
constexpr ObjectShape kPointShape{kPointMembers};
enum ProfileMember {
  kProfileCampaignId,
  kProfileStand,
  kProfilePosition,
  kProfileRollId,
  kProfileMeasuredAt,
  kProfilePoints
};
constexpr std::string_view kProfileMembers[] = {
    "campaign_id", "stand", "position", "roll_id", "measured_at", "points"};
constexpr ObjectShape kProfileShape{kProfileMembers, kProfilePoints, &kPointShape,
                                    kMaxProfilePoints};

}  // namespace

bool DecodeProfile(std::string_view body, int max_depth,
                   storage::ProfileIn* out, ApiError* error) {
  ScannedObject scanned;
  if (!ScanBody(body, max_depth, kProfileShape, &scanned, error)) return false;
  ObjectReader r(scanned, kProfileShape, error);
  if (!r.Text(kProfileCampaignId, &out->campaign_id) || !r.Stand(kProfileStand, &out->stand) ||
      !r.PositionOf(kProfilePosition, &out->position) ||
      !r.Text(kProfileRollId, &out->roll_id) ||
      !r.Timestamp(kProfileMeasuredAt, &out->measured_at) || !r.List(kProfilePoints)) {
    return false;
  }
  out->points.reserve(scanned.elements.size());
  for (size_t i = 0; i < scanned.elements.size(); ++i) {
    if (!r.ElementIsObject(i)) return false;
    ObjectReader e(scanned.elements[i], kPointShape, error, "points",
                   static_cast<int>(i));
    storage::ProfilePointIn& p = out->points.emplace_back();
    if (!e.Number(kPointX, &p.x_mm) || !e.Number(kPointWearUm, &p.wear_um)) return false;
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

std::string EncodeWearProfile(const engine::ProfileWear& wear) {
  const engine::PositionWear& c = wear.centre;
  const ProfilePrediction& p = wear.profile;
  JsonWriter w(512 + 64 * p.x_mm.size());
  w.BeginObject();
  w.Key("stand");
  w.String(StandName(c.stand));
  w.Key("position");
  w.String(PositionName(c.position));
  w.Key("roll_id");
  w.String(c.roll_id);
  w.Key("campaign_id");
  w.String(c.campaign_id);
  w.Key("model_version");
  w.Int(wear.model_version);
  w.Key("coils");
  w.Int(c.coils);
  w.Key("centre_wear_um");
  w.Double(c.predicted_wear_um);
  w.Key("shape");
  w.String(wear.shape.has_value() ? "calibrated" : "uncalibrated");
  // ProfileShapeNames(), as keys the compiler checks.
  static constexpr JsonKey kNames[kProfileShapeParameters] = {
      "beta2", "beta4", "alpha1", "alpha2", "alpha3"};
  const auto write_shape =
      [&](const std::array<double, kProfileShapeParameters>& values) {
        w.BeginObject();
        for (int i = 0; i < kProfileShapeParameters; ++i) {
          w.Key(kNames[i]);
          w.Double(values[i]);
        }
        w.EndObject();
      };
  w.Key("coefficients");
  if (wear.shape.has_value()) {
    write_shape(ProfileShapeValues(wear.shape->shape));
  } else {
    w.Null();
  }
  w.Key("standard_errors");
  if (wear.shape.has_value()) {
    write_shape(wear.shape->std_error);
  } else {
    w.Null();
  }
  w.Key("residual_sd_um");
  w.OptionalDouble(wear.shape.has_value()
                       ? std::optional<double>(wear.shape->residual_sd_um)
                       : std::nullopt);
  w.Key("x_mm");
  w.BeginArray();
  for (double x : p.x_mm) w.Double(x);
  w.EndArray();
  w.Key("predicted_wear_um");
  w.BeginArray();
  for (double v : p.wear_um) w.Double(v);
  w.EndArray();
  w.Key("interval_um");
  w.BeginArray();
  for (size_t j = 0; j < p.lo_um.size(); ++j) {
    w.BeginArray();
    w.Double(p.lo_um[j]);
    w.Double(p.hi_um[j]);
    w.EndArray();
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

}  // namespace rollwear::api
