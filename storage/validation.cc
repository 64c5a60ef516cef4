#include "storage/validation.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <vector>

#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::storage::internal {
namespace {

// The first broken rule as InvalidArgument "<path>: <rule>", the path
// made of the list's name and the element's index.
Status FirstBroken(const RuleViolations& broken, const char* list) {
  if (broken.empty()) return Status::Ok();
  const RuleViolation& v = broken.front();
  std::string path = v.element < 0
                         ? v.field
                         : std::string(list) + "[" + std::to_string(v.element) +
                               "]." + v.field;
  return Status::InvalidArgument(path + ": " + RuleMessage(v));
}

// The same as FailedPrecondition: the record is well-formed but does not
// fit what is stored (api.md: 422).
Status Inconsistent(const RuleViolations& broken, const char* list) {
  const Status s = FirstBroken(broken, list);
  return s.ok() ? s : Status::FailedPrecondition(s.message());
}

const CampaignRec* FindCampaign(const Catalog& c, const std::string& id) {
  auto it = c.campaigns.find(id);
  return it == c.campaigns.end() ? nullptr : &it->second;
}

Status UnknownCampaign(const std::string& id) {
  return Status::NotFound("campaign_id: unknown campaign " + id);
}

// A measurement or profile of the roll at (stand, position) of `rec`: that
// roll was mounted there, and the campaign ended before `measured_at`.
Status AdmitMeasuredRoll(const CampaignRec& rec, int stand, Position position,
                         const std::string& roll_id, UnixSeconds measured_at) {
  const std::string where =
      RollPositionName(stand, position) + " in campaign " + rec.id;
  const auto& mount = rec.mounts[RollPositionSlot(stand, position)];
  if (!mount.has_value()) {
    return Status::FailedPrecondition("stand: no roll mounted at " + where);
  }
  if (mount->roll_id != roll_id) {
    return Status::FailedPrecondition("roll_id: roll " + roll_id +
                                      " was not mounted at " + where +
                                      " (mounted: " + mount->roll_id + ")");
  }
  return Inconsistent(MeasurementTimeRules(rec.id, measured_at, rec.ended_at),
                      "");
}

}  // namespace

StoredCoil CanonicalCoil(const CoilIn& in) {
  StoredCoil c;
  c.coil_id = in.coil_id;
  c.campaign_id = in.campaign_id;
  c.seq = in.seq;
  c.grade = in.grade;
  for (const PassIn& p : in.passes) {
    c.passes.push_back(
        StoredPass{p, in.rolled_at, MergedExtraFields(in.extra, p.extra)});
  }
  std::stable_sort(c.passes.begin(), c.passes.end(),
                   [](const StoredPass& a, const StoredPass& b) {
                     return a.stand < b.stand;
                   });
  return c;
}

PassInput ToPassInput(const std::string& grade, const StoredPass& p) {
  PassInput in = PassInputFromRow(grade, p);
  in.extra = p.extra;
  return in;
}

bool SameMount(const MountedRollIn& a, const MountedRollIn& b) {
  return a.stand == b.stand && a.position == b.position &&
         a.roll_id == b.roll_id && a.roll_type == b.roll_type &&
         a.diameter_mm == b.diameter_mm && a.hardness_hb == b.hardness_hb &&
         a.extra == b.extra;
}

bool SameMeasurement(const MeasurementIn& a, const MeasurementIn& b) {
  return a.campaign_id == b.campaign_id && a.stand == b.stand &&
         a.position == b.position && a.roll_id == b.roll_id &&
         a.measured_at == b.measured_at &&
         a.wear_center_um == b.wear_center_um && a.extra == b.extra;
}

std::vector<std::string> PositionLabels(uint32_t mask) {
  std::vector<std::string> out;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (mask & (1u << slot)) {
      out.push_back(RollPositionName(SlotStand(slot), SlotPosition(slot)));
    }
  }
  return out;
}

// ------------------------------------------------------------- field rules

Status CheckRollChangeFields(const RollChangeIn& in) {
  return FirstBroken(RollChangeRules(in.campaign_id, MountRecords(in.rolls)),
                     "rolls");
}

Status CheckEndFields(const std::string& campaign_id, UnixSeconds) {
  // started_at is in the catalog: AdmitEnd checks ended_at against it.
  return FirstBroken(CampaignRules(campaign_id, 0, std::nullopt), "");
}

Status CheckCoilFields(const CoilIn& in) {
  return FirstBroken(
      CoilRules(in.coil_id, in.campaign_id, in.seq, in.grade, in.passes),
      "passes");
}

Status CheckMeasurementFields(const MeasurementIn& in) {
  return FirstBroken(MeasurementRules(in.campaign_id, in.stand, in.position,
                                      in.roll_id, in.wear_center_um),
                     "");
}

Status CheckProfileFields(const ProfileIn& in) {
  const Position pos = in.position;
  if (in.points.empty()) {
    return Status::InvalidArgument("points: a profile needs at least one point");
  }
  std::unordered_set<double> seen;
  for (size_t i = 0; i < in.points.size(); ++i) {
    const ProfilePointIn& p = in.points[i];
    RuleViolations broken = ProfilePointRules(
        in.campaign_id, in.stand, pos, in.roll_id, p.x_mm, p.wear_um);
    if (!broken.empty()) {
      RuleViolation& v = broken.front();
      if (v.field == "x_mm" || v.field == "wear_um") v.element = static_cast<int>(i);
      return FirstBroken(broken, "points");
    }
    if (std::abs(p.x_mm) > kMaxProfileXMm) {
      return Status::InvalidArgument(
          "points[" + std::to_string(i) + "].x_mm: must lie on the barrel (|x_mm| <= " +
          std::to_string(static_cast<int>(kMaxProfileXMm)) + "), got " +
          std::to_string(p.x_mm));
    }
    if (!seen.insert(p.x_mm).second) {
      return Status::InvalidArgument("points[" + std::to_string(i) +
                                     "].x_mm: duplicate point of the profile");
    }
  }
  return Status::Ok();
}

// ----------------------------------------------------------- catalog rules

Status AdmitRollChange(const Catalog& c, const RollChangeIn& in,
                       bool* unchanged) {
  *unchanged = false;
  if (const CampaignRec* rec = FindCampaign(c, in.campaign_id)) {
    bool same = rec->started_at == in.started_at && rec->extra == in.extra;
    int mounted = 0;
    for (const auto& m : rec->mounts) mounted += m.has_value() ? 1 : 0;
    same = same && mounted == static_cast<int>(in.rolls.size());
    for (const MountedRollIn& r : in.rolls) {
      const auto& m = rec->mounts[RollPositionSlot(r.stand, r.position)];
      same = same && m.has_value() && SameMount(*m, r);
    }
    if (!same) {
      return Status::AlreadyExists(
          "campaign_id: campaign " + in.campaign_id +
          " is already stored with a different roll change (started_at " +
          FormatTimestamp(rec->started_at) + ")");
    }
    *unchanged = true;
    return Status::Ok();
  }
  if (!c.open_campaign.empty()) {
    const CampaignRec& open = c.campaigns.at(c.open_campaign);
    if (in.started_at < open.started_at) {
      return Status::FailedPrecondition(
          "started_at: " + FormatTimestamp(in.started_at) +
          " is before the start of the open campaign " + c.open_campaign +
          " (" + FormatTimestamp(open.started_at) + "), which it would end");
    }
  }
  return Status::Ok();
}

void ApplyRollChange(const RollChangeIn& in, Catalog* c) {
  if (!c->open_campaign.empty()) {
    c->campaigns[c->open_campaign].ended_at = in.started_at;
  }
  CampaignRec rec;
  rec.id = in.campaign_id;
  rec.started_at = in.started_at;
  rec.extra = in.extra;
  for (const MountedRollIn& r : in.rolls) {
    const int slot = RollPositionSlot(r.stand, r.position);
    rec.mounts[slot] = r;
    c->positions_seen |= 1u << slot;
  }
  if (!c->campaigns.contains(in.campaign_id))
    c->order.push_back(in.campaign_id);
  c->campaigns[in.campaign_id] = std::move(rec);
  c->open_campaign = in.campaign_id;
  c->open_seqs.clear();
}

Status AdmitEnd(const Catalog& c, const std::string& campaign_id,
                UnixSeconds ended_at, bool* unchanged) {
  *unchanged = false;
  const CampaignRec* rec = FindCampaign(c, campaign_id);
  if (rec == nullptr) return UnknownCampaign(campaign_id);
  if (rec->ended_at.has_value()) {
    if (*rec->ended_at == ended_at) {
      *unchanged = true;
      return Status::Ok();
    }
    return Status::AlreadyExists("ended_at: campaign " + campaign_id +
                                 " already ended at " +
                                 FormatTimestamp(*rec->ended_at));
  }
  ROLLWEAR_RETURN_IF_ERROR(
      FirstBroken(CampaignRules(campaign_id, rec->started_at, ended_at), ""));
  return Status::Ok();
}

void ApplyEnd(const std::string& campaign_id, UnixSeconds ended_at,
              Catalog* c) {
  c->campaigns[campaign_id].ended_at = ended_at;
  if (c->open_campaign == campaign_id) {
    c->open_campaign.clear();
    c->open_seqs.clear();
  }
}

Status AdmitCoil(const Catalog& c, const CoilIn& in, const StoredCoil& coil,
                 const std::optional<StoredCoil>& stored, bool* unchanged,
                 bool check_seq) {
  *unchanged = false;
  if (stored.has_value()) {
    if (*stored == coil) {
      *unchanged = true;
      return Status::Ok();
    }
    return Status::AlreadyExists("coil_id: coil " + coil.coil_id +
                                 " is already stored with different content");
  }
  const CampaignRec* rec = FindCampaign(c, in.campaign_id);
  if (rec == nullptr) return UnknownCampaign(in.campaign_id);
  if (rec->ended_at.has_value()) {
    return Status::FailedPrecondition("campaign_id: campaign " +
                                      in.campaign_id + " has ended (at " +
                                      FormatTimestamp(*rec->ended_at) + ")");
  }
  uint32_t mounted = 0;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (rec->mounts[slot].has_value()) mounted |= 1u << slot;
  }
  for (size_t i = 0; i < in.passes.size(); ++i) {
    ROLLWEAR_RETURN_IF_ERROR(
        Inconsistent(PassMountRules(in.passes[i].stand, in.campaign_id, mounted,
                                    static_cast<int>(i)),
                     "passes"));
  }
  if (check_seq && c.open_campaign == in.campaign_id) {
    auto owner = c.open_seqs.find(in.seq);
    if (owner != c.open_seqs.end()) {
      return Status::FailedPrecondition(
          "seq: seq " + std::to_string(in.seq) + " of campaign " +
          in.campaign_id + " is already used by coil " + owner->second);
    }
  }
  return Status::Ok();
}

void AddExposure(const StoredCoil& coil, Catalog* c) {
  auto it = c->campaigns.find(coil.campaign_id);
  if (it == c->campaigns.end()) return;
  for (const StoredPass& p : coil.passes) {
    it->second.load[p.stand] += PassLoad(p);
    it->second.length_m[p.stand] += p.length_m;
  }
}

void ApplyCoil(const StoredCoil& coil, bool speculative, Catalog* c) {
  if (c->open_campaign == coil.campaign_id) {
    c->open_seqs.emplace(coil.seq, coil.coil_id);
  }
  AddExposure(coil, c);
  if (speculative) c->pending_coils[coil.coil_id] = coil;
}

Status AdmitMeasurement(const Catalog& c, const MeasurementIn& in,
                        bool* unchanged) {
  *unchanged = false;
  const CampaignRec* rec = FindCampaign(c, in.campaign_id);
  if (rec == nullptr) return UnknownCampaign(in.campaign_id);
  const int slot = RollPositionSlot(in.stand, in.position);
  const std::string where = RollPositionName(in.stand, in.position) +
                            " in campaign " + in.campaign_id;
  if (const auto& stored = rec->measurements[slot]) {
    if (SameMeasurement(*stored, in)) {
      *unchanged = true;
      return Status::Ok();
    }
    return Status::AlreadyExists("campaign_id: " + where +
                                 " is already measured with different content");
  }
  return AdmitMeasuredRoll(*rec, in.stand, in.position, in.roll_id,
                           in.measured_at);
}

Status AdmitProfile(const Catalog& c, const ProfileIn& in) {
  const CampaignRec* rec = FindCampaign(c, in.campaign_id);
  if (rec == nullptr) return UnknownCampaign(in.campaign_id);
  return AdmitMeasuredRoll(*rec, in.stand, in.position, in.roll_id,
                           in.measured_at);
}

void ApplyMeasurement(const MeasurementIn& in, Catalog* c) {
  c->campaigns[in.campaign_id]
      .measurements[RollPositionSlot(in.stand, in.position)] = in;
}

}  // namespace rollwear::storage::internal
