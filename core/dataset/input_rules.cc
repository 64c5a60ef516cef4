#include "core/dataset/input_rules.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <utility>

#include "core/dataset/timestamp.h"

namespace rollwear {
namespace {

// Shortest text that reads back as `v`.
std::string Num(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, r.ptr);
}

// Collects the violations of one record; `element` tags what it adds.
class Rules {
 public:
  explicit Rules(RuleViolations* out) : out_(out) {}

  void set_element(int element) { element_ = element; }

  void Add(const char* field, std::string rule, bool cites_value = false,
           std::string value = "", RuleKind kind = RuleKind::kRange) {
    out_->push_back(RuleViolation{field, element_, std::move(rule), cites_value,
                                  std::move(value), kind});
  }

  void NonEmpty(const char* field, std::string_view text) {
    if (text.empty()) Add(field, "must not be empty");
  }

  // False (and the violation) when `v` is not finite.
  bool Finite(const char* field, double v) {
    if (std::isfinite(v)) return true;
    Add(field, "must be a finite number");
    return false;
  }

  // Finite and > 0 (NaN and infinities are cited: "got nan").
  void Positive(const char* field, double v) {
    if (!(v > 0) || !std::isfinite(v)) Add(field, "must be > 0", true, Num(v));
  }

  // False (and the violation) when `stand` is not F1..F7.
  bool Stand(int stand) {
    if (stand >= kMinStand && stand <= kMaxStand) return true;
    Add("stand", "unknown stand " + std::to_string(stand) + " (want F1..F7)");
    return false;
  }

  bool PositionOk(Position p) {
    if (p == Position::kTop || p == Position::kBottom) return true;
    Add("position", "unknown position (want top or bottom)");
    return false;
  }

 private:
  RuleViolations* out_;
  int element_ = -1;
};

}  // namespace

std::string RuleMessage(const RuleViolation& v) {
  return v.cites_value ? v.rule + ", got " + v.value : v.rule;
}

RuleViolations CampaignRules(std::string_view campaign_id,
                             UnixSeconds started_at,
                             std::optional<UnixSeconds> ended_at) {
  RuleViolations out;
  Rules r(&out);
  r.NonEmpty("campaign_id", campaign_id);
  if (ended_at.has_value() && *ended_at < started_at) {
    r.Add("ended_at",
          "must not be before started_at (" + FormatTimestamp(started_at) + ")",
          true, FormatTimestamp(*ended_at));
  }
  return out;
}

namespace {

void AddMountRules(const MountRecord& m, Rules* r) {
  r->Stand(m.stand);
  r->PositionOk(m.position);
  r->NonEmpty("roll_id", m.roll_id);
  r->NonEmpty("roll_type", m.roll_type);
  r->Positive("diameter_mm", m.diameter_mm);
  r->Positive("hardness_hb", m.hardness_hb);
}

void AddCoilKeyRules(std::string_view coil_id, std::string_view campaign_id,
                     int64_t seq, std::string_view grade, Rules* r) {
  r->NonEmpty("coil_id", coil_id);
  r->NonEmpty("campaign_id", campaign_id);
  if (seq < 1) {
    r->Add("seq", "must be an integer >= 1", true, std::to_string(seq));
  } else if (seq > kMaxSeq) {
    r->Add("seq", "must be an integer <= " + std::to_string(kMaxSeq), true,
           std::to_string(seq));
  }
  r->NonEmpty("grade", grade);
}

void AddPassRules(const PassMeasures& p, Rules* r) {
  r->Stand(p.stand);
  r->Positive("force_kn", p.force_kn);
  r->Positive("width_mm", p.width_mm);
  r->Positive("length_m", p.length_m);
  r->Positive("entry_thickness_mm", p.entry_thickness_mm);
  r->Positive("exit_thickness_mm", p.exit_thickness_mm);
  if (p.exit_thickness_mm >= p.entry_thickness_mm) {
    r->Add("exit_thickness_mm",
           "must be < entry_thickness_mm (" + Num(p.entry_thickness_mm) + ")",
           true, Num(p.exit_thickness_mm));
  }
  r->Finite("temperature_c", p.temperature_c);
  r->Positive("speed_mps", p.speed_mps);
  r->Finite("shift_mm", p.shift_mm);
}

}  // namespace

RuleViolations MountRules(const MountRecord& m) {
  RuleViolations out;
  Rules r(&out);
  AddMountRules(m, &r);
  return out;
}

RuleViolations RollChangeRules(std::string_view campaign_id,
                               std::span<const MountRecord> rolls) {
  RuleViolations out;
  Rules r(&out);
  r.NonEmpty("campaign_id", campaign_id);
  if (rolls.empty()) r.Add("rolls", "must not be empty");
  int first[kNumRollPositionSlots];
  std::fill(std::begin(first), std::end(first), -1);
  for (size_t i = 0; i < rolls.size(); ++i) {
    const MountRecord& m = rolls[i];
    r.set_element(static_cast<int>(i));
    AddMountRules(m, &r);
    if (m.stand < kMinStand || m.stand > kMaxStand ||
        (m.position != Position::kTop && m.position != Position::kBottom)) {
      continue;
    }
    int& slot = first[RollPositionSlot(m.stand, m.position)];
    if (slot >= 0) {
      r.Add("stand",
            "duplicate roll position " + RollPositionName(m.stand, m.position) +
                " (also rolls[" + std::to_string(slot) + "])",
            false, "", RuleKind::kDuplicate);
    } else {
      slot = static_cast<int>(i);
    }
  }
  return out;
}

RuleViolations CoilKeyRules(std::string_view coil_id,
                            std::string_view campaign_id, int64_t seq,
                            std::string_view grade) {
  RuleViolations out;
  Rules r(&out);
  AddCoilKeyRules(coil_id, campaign_id, seq, grade, &r);
  return out;
}

RuleViolations PassRules(const PassMeasures& p) {
  RuleViolations out;
  Rules r(&out);
  AddPassRules(p, &r);
  return out;
}

RuleViolations CoilRules(
    std::string_view coil_id, std::string_view campaign_id, int64_t seq,
    std::string_view grade, size_t num_passes,
    const std::function<const PassMeasures&(size_t)>& pass_at) {
  RuleViolations out;
  Rules r(&out);
  AddCoilKeyRules(coil_id, campaign_id, seq, grade, &r);
  if (num_passes == 0) r.Add("passes", "must not be empty");
  int first[kMaxStand + 1];
  std::fill(std::begin(first), std::end(first), -1);
  for (size_t i = 0; i < num_passes; ++i) {
    const PassMeasures& p = pass_at(i);
    r.set_element(static_cast<int>(i));
    AddPassRules(p, &r);
    if (p.stand < kMinStand || p.stand > kMaxStand) continue;
    if (first[p.stand] >= 0) {
      r.Add("stand",
            "duplicate stand " + StandName(p.stand) + " (also passes[" +
                std::to_string(first[p.stand]) + "])",
            false, "", RuleKind::kDuplicate);
    } else {
      first[p.stand] = static_cast<int>(i);
    }
  }
  return out;
}

namespace {

// What a measurement and a profile point have in common: which roll.
void MeasuredRollRules(Rules* r, std::string_view campaign_id, int stand,
                       Position position, std::string_view roll_id) {
  r->NonEmpty("campaign_id", campaign_id);
  r->Stand(stand);
  r->PositionOk(position);
  r->NonEmpty("roll_id", roll_id);
}

}  // namespace

RuleViolations MeasurementRules(std::string_view campaign_id, int stand,
                                Position position, std::string_view roll_id,
                                double wear_center_um) {
  RuleViolations out;
  Rules r(&out);
  MeasuredRollRules(&r, campaign_id, stand, position, roll_id);
  r.Finite("wear_center_um", wear_center_um);
  return out;
}

RuleViolations ProfilePointRules(std::string_view campaign_id, int stand,
                                 Position position, std::string_view roll_id,
                                 double x_mm, double wear_um) {
  RuleViolations out;
  Rules r(&out);
  MeasuredRollRules(&r, campaign_id, stand, position, roll_id);
  r.Finite("x_mm", x_mm);
  r.Finite("wear_um", wear_um);
  return out;
}

RuleViolations PassMountRules(int stand, std::string_view campaign_id,
                              uint32_t mounted, int pass) {
  RuleViolations out;
  if (stand < kMinStand || stand > kMaxStand) return out;  // PassRules' job
  const uint32_t at_stand = (1u << RollPositionSlot(stand, Position::kTop)) |
                            (1u << RollPositionSlot(stand, Position::kBottom));
  if (mounted & at_stand) return out;
  std::string rule = "no roll mounted at " + StandName(stand) +
                     " in campaign " + std::string(campaign_id);
  std::string rolls;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (!(mounted & (1u << slot))) continue;
    if (!rolls.empty()) rolls += ", ";
    rolls += RollPositionName(SlotStand(slot), SlotPosition(slot));
  }
  rule += rolls.empty() ? " (it has no mounted rolls)"
                        : "; its rolls are at " + rolls;
  Rules r(&out);
  r.set_element(pass);
  r.Add("stand", std::move(rule));
  return out;
}

RuleViolations MeasurementTimeRules(
    std::string_view campaign_id, UnixSeconds measured_at,
    std::optional<UnixSeconds> campaign_ended_at) {
  RuleViolations out;
  Rules r(&out);
  if (!campaign_ended_at.has_value()) {
    r.Add("campaign_id", "campaign " + std::string(campaign_id) +
                             " has not ended: a roll is measured after its "
                             "campaign (end it first)");
  } else if (measured_at < *campaign_ended_at) {
    r.Add("measured_at",
          "must not be before the end of campaign " + std::string(campaign_id) +
              " (" + FormatTimestamp(*campaign_ended_at) +
              "): a roll is measured after it is taken out",
          true, FormatTimestamp(measured_at));
  }
  return out;
}

Status CheckRollPosition(int stand, Position position) {
  if (stand < kMinStand || stand > kMaxStand) {
    return Status::InvalidArgument("stand: unknown stand " +
                                   std::to_string(stand) + " (want F1..F7)");
  }
  if (position != Position::kTop && position != Position::kBottom) {
    return Status::InvalidArgument("position: want top or bottom");
  }
  return Status::Ok();
}

}  // namespace rollwear
