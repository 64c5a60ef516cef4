#include "api/request_encode.h"

#include <map>
#include <tuple>

#include "api/json_writer.h"
#include "core/dataset/dataset_io.h"

namespace rollwear::api {
namespace {

// The members a grinder's measurement and profile share: their key, roll
// and time.
template <typename Grinder>
void WriteMeasuredRoll(const Dataset& data, const Grinder& g, JsonWriter* w) {
  w->Key("campaign_id");
  w->String(data.campaigns[g.campaign].id);
  w->Key("stand");
  w->String(StandName(g.stand));
  w->Key("position");
  w->String(PositionName(g.position));
  w->Key("roll_id");
  w->String(g.roll_id);
  w->Key("measured_at");
  w->String(FormatTimestamp(g.measured_at));
}

}  // namespace

std::string RollChangeRequest(const Dataset& data, int campaign,
                              const std::vector<int>& mounts) {
  const Campaign& c = data.campaigns[campaign];
  JsonWriter w(128 + 160 * mounts.size());
  w.BeginObject();
  w.Key("campaign_id");
  w.String(c.id);
  w.Key("started_at");
  w.String(FormatTimestamp(c.started_at));
  w.Key("rolls");
  w.BeginArray();
  for (int i : mounts) {
    const Mount& m = data.mounts[i];
    w.BeginObject();
    w.Key("stand");
    w.String(StandName(m.stand));
    w.Key("position");
    w.String(PositionName(m.position));
    w.Key("roll_id");
    w.String(m.roll_id);
    w.Key("roll_type");
    w.String(data.roll_types[m.roll_type]);
    w.Key("diameter_mm");
    w.Double(m.diameter_mm);
    w.Key("hardness_hb");
    w.Double(m.hardness_hb);
    w.EndObject();
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

std::string CoilRequest(const Dataset& data, const std::vector<int>& passes) {
  const Pass& first = data.passes[passes.at(0)];
  JsonWriter w(160 + 240 * passes.size());
  w.BeginObject();
  w.Key("coil_id");
  w.String(data.coil_ids[first.coil]);
  w.Key("campaign_id");
  w.String(data.campaigns[first.campaign].id);
  w.Key("seq");
  w.Int(first.seq);
  w.Key("rolled_at");
  w.String(FormatTimestamp(first.rolled_at));
  w.Key("grade");
  w.String(data.grades[first.grade]);
  w.Key("passes");
  w.BeginArray();
  for (int i : passes) {
    const Pass& p = data.passes[i];
    w.BeginObject();
    w.Key("stand");
    w.String(StandName(p.stand));
    w.Key("force_kn");
    w.Double(p.force_kn);
    w.Key("width_mm");
    w.Double(p.width_mm);
    w.Key("length_m");
    w.Double(p.length_m);
    w.Key("entry_thickness_mm");
    w.Double(p.entry_thickness_mm);
    w.Key("exit_thickness_mm");
    w.Double(p.exit_thickness_mm);
    w.Key("temperature_c");
    w.Double(p.temperature_c);
    w.Key("speed_mps");
    w.Double(p.speed_mps);
    w.Key("lubrication");
    w.Int(p.lubrication ? 1 : 0);
    w.Key("shift_mm");
    w.Double(p.shift_mm);
    w.EndObject();
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

std::string CampaignEndRequest(const Dataset& data, int campaign) {
  JsonWriter w(48);
  w.BeginObject();
  w.Key("ended_at");
  w.String(FormatTimestamp(data.campaigns[campaign].ended_at));
  w.EndObject();
  return w.Take();
}

std::string MeasurementRequest(const Dataset& data, int measurement) {
  const Measurement& m = data.measurements[measurement];
  JsonWriter w(192);
  w.BeginObject();
  WriteMeasuredRoll(data, m, &w);
  w.Key("wear_center_um");
  w.Double(m.wear_center_um);
  w.EndObject();
  return w.Take();
}

std::vector<std::vector<int>> ProfileGroups(const Dataset& data) {
  std::map<std::tuple<int, int, int>, size_t> index;
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < data.profile_points.size(); ++i) {
    const ProfilePoint& p = data.profile_points[i];
    const auto [it, fresh] = index.emplace(
        std::make_tuple(p.campaign, p.stand, static_cast<int>(p.position)),
        groups.size());
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(static_cast<int>(i));
  }
  return groups;
}

std::string ProfileRequest(const Dataset& data, const std::vector<int>& points) {
  const ProfilePoint& first = data.profile_points[points.front()];
  JsonWriter w(192 + 48 * points.size());
  w.BeginObject();
  WriteMeasuredRoll(data, first, &w);
  w.Key("points");
  w.BeginArray();
  for (int i : points) {
    const ProfilePoint& p = data.profile_points[i];
    w.BeginObject();
    w.Key("x_mm");
    w.Double(p.x_mm);
    w.Key("wear_um");
    w.Double(p.wear_um);
    w.EndObject();
  }
  w.EndArray();
  w.EndObject();
  return w.Take();
}

}  // namespace rollwear::api
