#include "storage/store_quality.h"

#include <utility>

namespace rollwear::storage::internal {
namespace {

// The kind named at the head of a stored flag ("negative_wear: ...").
DataQualityKind KindOfFlag(const std::string& flag) {
  for (int k = 0; k < kNumDataQualityKinds; ++k) {
    const auto kind = static_cast<DataQualityKind>(k);
    if (flag.rfind(std::string(DataQualityKindName(kind)) + ":", 0) == 0) {
      return kind;
    }
  }
  return DataQualityKind::kNegativeWear;
}

}  // namespace

std::vector<std::string> SuspectFlags(const DataQuality& quality) {
  std::vector<std::string> flags(quality.suspect.size());
  for (const DataQualityIssue& issue : quality.issues) {
    if (issue.measurement < 0) continue;
    flags[issue.measurement] =
        std::string(DataQualityKindName(issue.kind)) + ": " + issue.reason;
  }
  return flags;
}

std::string JudgeMeasurement(Dataset stored, const MeasurementIn& in) {
  int campaign = -1;
  for (size_t c = 0; c < stored.campaigns.size(); ++c) {
    if (stored.campaigns[c].id == in.campaign_id)
      campaign = static_cast<int>(c);
  }
  if (campaign < 0) return "";
  Measurement m;
  m.campaign = campaign;
  m.stand = in.stand;
  m.position = in.position;
  m.roll_id = in.roll_id;
  m.measured_at = in.measured_at;
  m.wear_center_um = in.wear_center_um;
  stored.measurements.push_back(std::move(m));
  const DataQuality quality = AssessDataQuality(stored);
  return SuspectFlags(quality).back();
}

FittingData FittingDataOf(Dataset all,
                          const std::vector<std::string>& stored_flags) {
  FittingData out;
  out.quality = AssessDataQuality(all);
  for (size_t i = 0; i < stored_flags.size() && i < all.measurements.size();
       ++i) {
    if (stored_flags[i].empty() || !out.quality.suspect[i].empty()) continue;
    const Measurement& m = all.measurements[i];
    DataQualityIssue issue;
    issue.kind = KindOfFlag(stored_flags[i]);
    issue.file = "measurements";
    issue.measurement = static_cast<int>(i);
    issue.where = RollPositionName(m.stand, m.position) + " of campaign '" +
                  all.campaigns[m.campaign].id + "'";
    issue.value_um = m.wear_center_um;
    issue.reason = "flagged when stored: " + stored_flags[i];
    out.quality.suspect[i] = issue.reason;
    out.quality.issues.push_back(std::move(issue));
  }
  out.fit = WithoutSuspects(all, out.quality);
  out.all = std::move(all);
  return out;
}

int64_t FlagImported(const Dataset& data, const ImportPlan& plan,
                     const std::vector<std::string>& suspect,
                     Catalog* catalog) {
  int64_t n = 0;
  for (size_t i = 0; i < suspect.size() && i < data.measurements.size(); ++i) {
    if (!plan.new_measurement[i] || suspect[i].empty()) continue;
    const Measurement& m = data.measurements[i];
    auto& stored = catalog->campaigns[data.campaigns[m.campaign].id]
                       .measurements[RollPositionSlot(m.stand, m.position)];
    if (stored.has_value()) stored->suspect = suspect[i];
    ++n;
  }
  return n;
}

}  // namespace rollwear::storage::internal
