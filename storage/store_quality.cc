#include "storage/store_quality.h"

#include <algorithm>
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

// A stored flag: "<kind>: <reason>" (measurements.suspect, the API's
// "suspect").
std::string FlagText(DataQualityKind kind, const std::string& reason) {
  return std::string(DataQualityKindName(kind)) + ": " + reason;
}

}  // namespace

std::vector<std::string> SuspectFlags(const DataQuality& quality) {
  std::vector<std::string> flags(quality.suspect.size());
  for (const DataQualityIssue& issue : quality.issues) {
    if (issue.measurement < 0) continue;
    flags[issue.measurement] = FlagText(issue.kind, issue.reason);
  }
  return flags;
}

std::vector<ReadingExposure> JudgedReadings(const Catalog& c,
                                            const MeasurementIn& in,
                                            int window) {
  // The window's first campaign: the earlier of `in`'s own and the
  // `window`-th newest.
  const auto own = std::find(c.order.rbegin(), c.order.rend(), in.campaign_id);
  if (own == c.order.rend()) return {};
  const size_t own_index = c.order.size() - 1 - (own - c.order.rbegin());
  const size_t newest = c.order.size() > static_cast<size_t>(window)
                            ? c.order.size() - window
                            : 0;
  std::vector<ReadingExposure> readings;
  for (size_t k = std::min(own_index, newest); k < c.order.size(); ++k) {
    const CampaignRec& rec = c.campaigns.at(c.order[k]);
    for (const auto& m : rec.measurements) {
      if (!m.has_value()) continue;
      readings.push_back(
          {m->wear_center_um, rec.load[m->stand], rec.length_m[m->stand]});
    }
  }
  const CampaignRec& rec = c.campaigns.at(in.campaign_id);
  readings.push_back(
      {in.wear_center_um, rec.load[in.stand], rec.length_m[in.stand]});
  return readings;
}

std::string JudgeMeasurement(const std::vector<ReadingExposure>& readings) {
  DataQualityKind kind = DataQualityKind::kNegativeWear;
  const std::string reason = JudgeLastReading(readings, &kind);
  return reason.empty() ? "" : FlagText(kind, reason);
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
