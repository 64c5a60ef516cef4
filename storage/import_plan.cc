#include "storage/import_plan.h"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"
#include "storage/validation.h"

namespace rollwear::storage::internal {
namespace {

std::string Row(const char* table, size_t i) {
  return std::string(table) + "[" + std::to_string(i) + "]";
}

// Field `field` of row i of a table of `rows` rows: "measurements.csv:5
// wear_center_um" when the dataset was read from files (one line per row
// known), else "measurements[4].wear_center_um".
std::string Locate(const std::vector<int>& lines, size_t rows, const char* file,
                   const char* table, size_t i, const char* field) {
  if (lines.size() == rows && i < rows) {
    return std::string(file) + ":" + std::to_string(lines[i]) + " " + field;
  }
  return Row(table, i) + "." + field;
}

Status Bad(const std::string& path, const std::string& rule) {
  return Status::InvalidArgument(path + ": " + rule);
}

bool InRange(int i, size_t n) { return i >= 0 && static_cast<size_t>(i) < n; }

// The first broken rule of row `at` ("passes[12]."), `where` appended.
Status FirstBroken(const RuleViolations& broken, const std::string& at,
                   const std::string& where = "") {
  if (broken.empty()) return Status::Ok();
  return Bad(at + broken.front().field, RuleMessage(broken.front()) + where);
}

Status CheckExtras(const ExtraColumns& e, size_t rows, const char* table) {
  if (e.numeric.size() != e.numeric_names.size() ||
      e.factor.size() != e.factor_names.size() ||
      e.factor_levels.size() != e.factor_names.size()) {
    return Bad(std::string(table) + " extra columns", "inconsistent lists");
  }
  for (const auto& col : e.numeric) {
    if (col.size() != rows) {
      return Bad(std::string(table) + " extra columns",
                 "a column does not have one value per row");
    }
  }
  for (size_t c = 0; c < e.factor.size(); ++c) {
    if (e.factor[c].size() != rows) {
      return Bad(std::string(table) + " extra columns",
                 "a column does not have one value per row");
    }
    for (int level : e.factor[c]) {
      if (!InRange(level, e.factor_levels[c].size())) {
        return Bad(std::string(table) + " extra column " + e.factor_names[c],
                   "level index out of range");
      }
    }
  }
  return Status::Ok();
}

// Mount `i` of `d` as the store keeps it (its extra columns as fields).
MountedRollIn ToMount(const Dataset& d, size_t i) {
  const Mount& m = d.mounts[i];
  return MountedRollIn{m.stand,       m.position,
                       m.roll_id,     d.roll_types[m.roll_type],
                       m.diameter_mm, m.hardness_hb,
                       ExtraFieldsOfRow(d.mount_extra, i)};
}

// Measurement `i` of `d` as the store keeps it.
MeasurementIn ToMeasurement(const Dataset& d, size_t i) {
  const Measurement& m = d.measurements[i];
  return MeasurementIn{d.campaigns[m.campaign].id,
                       m.stand,
                       m.position,
                       m.roll_id,
                       m.measured_at,
                       m.wear_center_um,
                       ExtraFieldsOfRow(d.measurement_extra, i),
                       /*suspect=*/""};
}

// `mounted[c]`: bit per roll position slot campaign c mounts.
Status CheckPasses(const Dataset& d, const std::vector<uint32_t>& mounted) {
  struct CoilInfo {
    int campaign, seq, grade, first_row;
    uint32_t stands;
  };
  std::vector<CoilInfo> coils(d.coil_ids.size(), CoilInfo{-1, 0, -1, -1, 0});
  std::unordered_map<uint64_t, int> seq_owner;
  for (size_t i = 0; i < d.passes.size(); ++i) {
    const Pass& p = d.passes[i];
    const std::string at = Row("passes", i) + ".";
    if (!InRange(p.campaign, d.campaigns.size())) {
      return Bad(at + "campaign_id", "unknown campaign (index out of range)");
    }
    if (!InRange(p.coil, d.coil_ids.size())) {
      return Bad(at + "coil_id", "unknown coil (index out of range)");
    }
    if (!InRange(p.grade, d.grades.size())) {
      return Bad(at + "grade", "unknown grade (index out of range)");
    }
    const std::string where = " (coil " + d.coil_ids[p.coil] + " at F" +
                              std::to_string(p.stand) + ")";
    ROLLWEAR_RETURN_IF_ERROR(
        FirstBroken(CoilKeyRules(d.coil_ids[p.coil], d.campaigns[p.campaign].id,
                                 p.seq, d.grades[p.grade]),
                    at, where));
    ROLLWEAR_RETURN_IF_ERROR(FirstBroken(PassRules(p), at, where));
    ROLLWEAR_RETURN_IF_ERROR(
        FirstBroken(PassMountRules(p.stand, d.campaigns[p.campaign].id,
                                   mounted[p.campaign]),
                    at, where));
    CoilInfo& info = coils[p.coil];
    if (info.first_row < 0) {
      info = CoilInfo{p.campaign, p.seq, p.grade, static_cast<int>(i), 0};
      const uint64_t key = (static_cast<uint64_t>(p.campaign) << 32) |
                           static_cast<uint32_t>(p.seq);
      auto [owner, fresh] = seq_owner.emplace(key, p.coil);
      if (!fresh) {
        return Bad(at + "seq",
                   "seq " + std::to_string(p.seq) + " of campaign " +
                       d.campaigns[p.campaign].id +
                       " is already used by coil " + d.coil_ids[owner->second]);
      }
    } else {
      const std::string first =
          " than passes[" + std::to_string(info.first_row) + "]" + where;
      if (info.campaign != p.campaign) {
        return Bad(at + "campaign_id", "differs for the same coil_id" + first);
      }
      if (info.seq != p.seq) {
        return Bad(at + "seq", "differs for the same coil_id" + first);
      }
      if (info.grade != p.grade) {
        return Bad(at + "grade", "differs for the same coil_id" + first);
      }
      if (info.stands & (1u << p.stand)) {
        return Bad(at + "stand", "duplicate key (coil_id, stand)" + where);
      }
    }
    info.stands |= 1u << p.stand;
  }
  return Status::Ok();
}

// The dataset row of the first pass of `mine` (a coil of `d`) that differs
// from the stored coil; `first` (the coil's first row) when the keys or the
// stands differ.
size_t DifferingRow(const Dataset& d, const StoredCoil& mine,
                    const StoredCoil& stored, size_t first) {
  if (mine.campaign_id != stored.campaign_id || mine.seq != stored.seq ||
      mine.grade != stored.grade ||
      mine.passes.size() != stored.passes.size()) {
    return first;
  }
  for (size_t k = 0; k < mine.passes.size(); ++k) {
    if (mine.passes[k] == stored.passes[k]) continue;
    for (size_t r = first; r < d.passes.size(); ++r) {
      if (d.passes[r].coil == d.passes[first].coil &&
          d.passes[r].stand == mine.passes[k].stand) {
        return r;
      }
    }
    break;
  }
  return first;
}

// The measurements: rules, campaign end, keys and their mounts (`mount_of`:
// campaign * kNumRollPositionSlots + slot -> mount index or -1).
Status CheckMeasurements(const Dataset& d, const std::vector<int>& mount_of) {
  std::vector<char> measured(mount_of.size(), 0);
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    const std::string at = Row("measurements", i) + ".";
    if (!InRange(m.campaign, d.campaigns.size())) {
      return Bad(at + "campaign_id", "unknown campaign (index out of range)");
    }
    ROLLWEAR_RETURN_IF_ERROR(
        FirstBroken(MeasurementRules(d.campaigns[m.campaign].id, m.stand,
                                     m.position, m.roll_id, m.wear_center_um),
                    at));
    const Campaign& campaign = d.campaigns[m.campaign];
    ROLLWEAR_RETURN_IF_ERROR(FirstBroken(
        MeasurementTimeRules(campaign.id, m.measured_at, campaign.ended_at),
        at));
    const size_t key = m.campaign * kNumRollPositionSlots +
                       RollPositionSlot(m.stand, m.position);
    const std::string where = RollPositionName(m.stand, m.position) +
                              " of campaign " + d.campaigns[m.campaign].id;
    if (measured[key]) {
      return Bad(at + "position",
                 "duplicate key (campaign_id, stand, position): " + where);
    }
    measured[key] = 1;
    if (mount_of[key] < 0) {
      return Bad(at + "stand", "no mount for " + where);
    }
    if (d.mounts[mount_of[key]].roll_id != m.roll_id) {
      return Bad(at + "roll_id",
                 "roll_id must match the mount: " + where + " mounted " +
                     d.mounts[mount_of[key]].roll_id + ", got " + m.roll_id);
    }
  }
  return Status::Ok();
}

}  // namespace

Status CheckDataset(const Dataset& d) {
  std::unordered_set<std::string> ids;
  for (size_t i = 0; i < d.campaigns.size(); ++i) {
    const Campaign& c = d.campaigns[i];
    const std::string at = Row("campaigns", i) + ".";
    ROLLWEAR_RETURN_IF_ERROR(
        FirstBroken(CampaignRules(c.id, c.started_at, c.ended_at), at,
                    c.id.empty() ? "" : " (campaign " + c.id + ")"));
    if (!ids.insert(c.id).second) {
      return Bad(at + "campaign_id", "duplicate campaign_id " + c.id);
    }
  }
  for (const auto& label : d.roll_types) {
    if (label.empty()) return Bad("roll_types", "labels must not be empty");
  }
  for (const auto& label : d.grades) {
    if (label.empty()) return Bad("grades", "labels must not be empty");
  }
  std::unordered_set<std::string> coil_ids;
  for (const auto& id : d.coil_ids) {
    if (id.empty()) return Bad("coil_ids", "coil_id must not be empty");
    if (!coil_ids.insert(id).second) {
      return Bad("coil_ids", "coil_id " + id + " is listed twice");
    }
  }
  std::vector<int> mount_of(d.campaigns.size() * kNumRollPositionSlots, -1);
  std::vector<uint32_t> mounted(d.campaigns.size(), 0);
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    const Mount& m = d.mounts[i];
    const std::string at = Row("mounts", i) + ".";
    if (!InRange(m.campaign, d.campaigns.size())) {
      return Bad(at + "campaign_id", "unknown campaign (index out of range)");
    }
    if (!InRange(m.roll_type, d.roll_types.size())) {
      return Bad(at + "roll_type", "unknown roll type (index out of range)");
    }
    ROLLWEAR_RETURN_IF_ERROR(FirstBroken(
        MountRules({m.stand, m.position, m.roll_id, d.roll_types[m.roll_type],
                    m.diameter_mm, m.hardness_hb}),
        at));
    int& slot = mount_of[m.campaign * kNumRollPositionSlots +
                         RollPositionSlot(m.stand, m.position)];
    if (slot >= 0) {
      return Bad(at + "position",
                 "duplicate key (campaign_id, stand, position): " +
                     RollPositionName(m.stand, m.position) + " of campaign " +
                     d.campaigns[m.campaign].id + " (also mounts[" +
                     std::to_string(slot) + "])");
    }
    slot = static_cast<int>(i);
    mounted[m.campaign] |= 1u << RollPositionSlot(m.stand, m.position);
  }
  ROLLWEAR_RETURN_IF_ERROR(CheckPasses(d, mounted));
  ROLLWEAR_RETURN_IF_ERROR(CheckMeasurements(d, mount_of));
  ROLLWEAR_RETURN_IF_ERROR(
      CheckExtras(d.campaign_extra, d.campaigns.size(), "campaigns"));
  ROLLWEAR_RETURN_IF_ERROR(
      CheckExtras(d.mount_extra, d.mounts.size(), "mounts"));
  ROLLWEAR_RETURN_IF_ERROR(
      CheckExtras(d.pass_extra, d.passes.size(), "passes"));
  return CheckExtras(d.measurement_extra, d.measurements.size(),
                     "measurements");
}

std::vector<StoredCoil> DatasetCoils(const Dataset& d) {
  std::vector<StoredCoil> coils(d.coil_ids.size());
  for (size_t i = 0; i < d.passes.size(); ++i) {
    const Pass& p = d.passes[i];
    StoredCoil& c = coils[p.coil];
    if (c.coil_id.empty()) {
      c.coil_id = d.coil_ids[p.coil];
      c.campaign_id = d.campaigns[p.campaign].id;
      c.seq = p.seq;
      c.grade = d.grades[p.grade];
    }
    c.passes.push_back(
        StoredPass{static_cast<const PassMeasures&>(p), p.rolled_at,
                   ExtraFieldsOfRow(d.pass_extra, i)});
  }
  for (StoredCoil& c : coils) {
    std::stable_sort(c.passes.begin(), c.passes.end(),
                     [](const StoredPass& a, const StoredPass& b) {
                       return a.stand < b.stand;
                     });
  }
  return coils;
}

namespace {

// PlanImport's coils: each new, or stored alike (skipped), or a conflict.
Status PlanCoils(const Dataset& d, const DatasetLines& lines,
                 const std::vector<StoredCoil>& coils, const Catalog& catalog,
                 const CoilLookup& lookup_coil, const SeqLookup& lookup_seq,
                 ImportPlan* out) {
  ImportPlan& plan = *out;
  std::vector<size_t> first_pass(coils.size(), 0);  // coil -> its first row
  for (size_t r = d.passes.size(); r-- > 0;) first_pass[d.passes[r].coil] = r;
  for (size_t i = 0; i < coils.size(); ++i) {
    const StoredCoil& coil = coils[i];
    auto at = [&](const char* field) {
      return Locate(lines.passes, d.passes.size(), "coils.csv", "passes",
                    first_pass[i], field);
    };
    ROLLWEAR_ASSIGN_OR_RETURN(const std::optional<StoredCoil> stored,
                              lookup_coil(coil.coil_id));
    if (stored.has_value()) {
      if (*stored != coil) {
        first_pass[i] = DifferingRow(d, coil, *stored, first_pass[i]);
        return Status::AlreadyExists(at("coil_id") + ": coil " + coil.coil_id +
                                     " is already stored with different "
                                     "content");
      }
      plan.new_coil[i] = 0;
      continue;
    }
    if (catalog.campaigns.count(coil.campaign_id) > 0) {
      ROLLWEAR_ASSIGN_OR_RETURN(const std::optional<std::string> owner,
                                lookup_seq(coil.campaign_id, coil.seq));
      if (owner.has_value()) {
        return Status::FailedPrecondition(
            at("seq") + ": seq " + std::to_string(coil.seq) + " of campaign " +
            coil.campaign_id + " is already used by coil " + *owner +
            " (this is coil " + coil.coil_id + ")");
      }
    }
    ++plan.num_coils;
  }
  return Status::Ok();
}

}  // namespace

StatusOr<ImportPlan> PlanImport(const Dataset& d, const DatasetLines* where,
                                const std::vector<StoredCoil>& coils,
                                const Catalog& catalog,
                                const CoilLookup& lookup_coil,
                                const SeqLookup& lookup_seq) {
  const DatasetLines none;
  const DatasetLines& lines = where != nullptr ? *where : none;
  ImportPlan plan;
  plan.new_campaign.assign(d.campaigns.size(), 1);
  plan.new_mount.assign(d.mounts.size(), 1);
  plan.new_coil.assign(d.coil_ids.size(), 1);
  plan.new_measurement.assign(d.measurements.size(), 1);
  for (size_t i = 0; i < d.campaigns.size(); ++i) {
    const Campaign& c = d.campaigns[i];
    auto it = catalog.campaigns.find(c.id);
    if (it == catalog.campaigns.end()) {
      ++plan.num_campaigns;
      continue;
    }
    const CampaignRec& rec = it->second;
    if (rec.started_at != c.started_at || !rec.ended_at.has_value() ||
        *rec.ended_at != c.ended_at ||
        rec.extra != ExtraFieldsOfRow(d.campaign_extra, i)) {
      return Status::AlreadyExists(
          Locate(lines.campaigns, d.campaigns.size(), "campaigns.csv",
                 "campaigns", i, "campaign_id") +
          ": campaign " + c.id +
          " is already stored with different content (started_at " +
          FormatTimestamp(rec.started_at) + ", ended_at " +
          (rec.ended_at ? FormatTimestamp(*rec.ended_at) : "open") + ")");
    }
    plan.new_campaign[i] = 0;
  }
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    const Mount& m = d.mounts[i];
    if (plan.new_campaign[m.campaign]) continue;
    const CampaignRec& rec = catalog.campaigns.at(d.campaigns[m.campaign].id);
    const auto& stored = rec.mounts[RollPositionSlot(m.stand, m.position)];
    if (!stored.has_value()) continue;
    if (!SameMount(*stored, ToMount(d, i))) {
      return Status::AlreadyExists(
          Locate(lines.mounts, d.mounts.size(), "mounts.csv", "mounts", i,
                 "stand") +
          ": " + RollPositionName(m.stand, m.position) + " of campaign " +
          rec.id + " is already stored with different content");
    }
    plan.new_mount[i] = 0;
  }
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    if (plan.new_campaign[m.campaign]) {
      ++plan.num_measurements;
      continue;
    }
    const CampaignRec& rec = catalog.campaigns.at(d.campaigns[m.campaign].id);
    const auto& stored =
        rec.measurements[RollPositionSlot(m.stand, m.position)];
    if (!stored.has_value()) {
      ++plan.num_measurements;
      continue;
    }
    if (!SameMeasurement(*stored, ToMeasurement(d, i))) {
      return Status::AlreadyExists(
          Locate(lines.measurements, d.measurements.size(), "measurements.csv",
                 "measurements", i, "campaign_id") +
          ": " + RollPositionName(m.stand, m.position) + " of campaign " +
          rec.id + " is already measured with different content");
    }
    plan.new_measurement[i] = 0;
  }
  ROLLWEAR_RETURN_IF_ERROR(
      PlanCoils(d, lines, coils, catalog, lookup_coil, lookup_seq, &plan));
  return plan;
}

ImportCounts CountImport(const ImportPlan& plan) {
  auto count = [](const std::vector<char>& is_new) {
    ImportTableCounts c;
    for (char n : is_new) ++(n ? c.added : c.unchanged);
    return c;
  };
  return ImportCounts{count(plan.new_campaign), count(plan.new_mount),
                      count(plan.new_coil), count(plan.new_measurement),
                      plan.profiles};
}

void ApplyImport(const Dataset& d, const std::vector<StoredCoil>& coils,
                 const ImportPlan& plan, bool speculative, Catalog* catalog) {
  for (size_t i = 0; i < d.campaigns.size(); ++i) {
    if (!plan.new_campaign[i]) continue;
    CampaignRec rec;
    rec.id = d.campaigns[i].id;
    rec.started_at = d.campaigns[i].started_at;
    rec.ended_at = d.campaigns[i].ended_at;
    rec.extra = ExtraFieldsOfRow(d.campaign_extra, i);
    if (!catalog->campaigns.contains(rec.id)) catalog->order.push_back(rec.id);
    catalog->campaigns[rec.id] = std::move(rec);
  }
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    if (!plan.new_mount[i]) continue;
    const Mount& m = d.mounts[i];
    const int slot = RollPositionSlot(m.stand, m.position);
    catalog->campaigns[d.campaigns[m.campaign].id].mounts[slot] = ToMount(d, i);
    catalog->positions_seen |= 1u << slot;
  }
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    if (!plan.new_measurement[i]) continue;
    ApplyMeasurement(ToMeasurement(d, i), catalog);
  }
  for (size_t i = 0; i < coils.size(); ++i) {
    if (!plan.new_coil[i]) continue;
    AddExposure(coils[i], catalog);
    if (speculative) catalog->pending_coils[coils[i].coil_id] = coils[i];
  }
}

}  // namespace rollwear::storage::internal
