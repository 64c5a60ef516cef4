#include "core/model/covariates.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

namespace rollwear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void AddExtras(const ExtraColumns& extra, CovariateLevel level,
               CovariateSource numeric, CovariateSource factor,
               std::vector<CovariateSpec>* out) {
  for (size_t i = 0; i < extra.numeric_names.size(); ++i) {
    out->push_back({extra.numeric_names[i], numeric, level,
                    CovariateKind::kNumeric, static_cast<int>(i)});
  }
  for (size_t i = 0; i < extra.factor_names.size(); ++i) {
    out->push_back({extra.factor_names[i], factor, level,
                    CovariateKind::kFactor, static_cast<int>(i), false,
                    extra.factor_levels[i]});
  }
}

// The index of `label` in the sorted `levels`; NaN when absent.
double SortedLevelIndex(const std::vector<std::string>& levels, const std::string& label) {
  const auto it = std::lower_bound(levels.begin(), levels.end(), label);
  if (it == levels.end() || *it != label) return kNaN;
  return static_cast<double>(it - levels.begin());
}

}  // namespace

std::vector<CovariateSpec> CovariateCatalog(const Dataset& data) {
  using L = CovariateLevel;
  using K = CovariateKind;
  using S = CovariateSource;
  std::vector<CovariateSpec> c = {
      {"force_kn", S::kForce, L::kPass, K::kNumeric},
      {"width_mm", S::kWidth, L::kPass, K::kNumeric},
      {"length_m", S::kLength, L::kPass, K::kNumeric},
      {"entry_thickness_mm", S::kEntryThickness, L::kPass, K::kNumeric},
      {"exit_thickness_mm", S::kExitThickness, L::kPass, K::kNumeric},
      {"temperature_c", S::kTemperature, L::kPass, K::kNumeric},
      {"speed_mps", S::kSpeed, L::kPass, K::kNumeric},
      {"lubrication", S::kLubrication, L::kPass, K::kFlag},
      {"shift_mm", S::kShift, L::kPass, K::kNumeric},
      {"specific_force_kn_per_mm", S::kSpecificForce, L::kPass, K::kNumeric},
      {"contact_length_mm", S::kContactLength, L::kPass, K::kNumeric},
      {"reduction", S::kReduction, L::kPass, K::kNumeric},
      {"campaign_length_before_m", S::kLengthBefore, L::kPass, K::kNumeric, -1,
       true},
      {"campaign_coils_before", S::kCoilsBefore, L::kPass, K::kNumeric, -1,
       true},
      {"hours_since_mount", S::kHoursSinceMount, L::kPass, K::kNumeric, -1,
       true},
      {"diameter_mm", S::kDiameter, L::kRoll, K::kNumeric},
      {"hardness_hb", S::kHardness, L::kRoll, K::kNumeric},
      {"started_at", S::kStartedAt, L::kCampaign, K::kNumeric},
      {kCoolingHoursName, S::kCoolingHours, L::kMeasurement, K::kNumeric},
      {"measured_at", S::kMeasuredAt, L::kMeasurement, K::kNumeric},
      {kCellCovariateName, S::kCell, L::kPass, K::kNumeric},
      {kRollCampaignsBeforeName,
       S::kRollCampaignsBefore,
       L::kRoll,
       K::kNumeric,
       -1,
       false,
       {},
       /*locate_only=*/true},
  };
  AddExtras(data.pass_extra, L::kPass, S::kPassExtraNumeric,
            S::kPassExtraFactor, &c);
  AddExtras(data.mount_extra, L::kRoll, S::kMountExtraNumeric,
            S::kMountExtraFactor, &c);
  AddExtras(data.campaign_extra, L::kCampaign, S::kCampaignExtraNumeric,
            S::kCampaignExtraFactor, &c);
  AddExtras(data.measurement_extra, L::kMeasurement,
            S::kMeasurementExtraNumeric, S::kMeasurementExtraFactor, &c);
  // After the extras: a dataset without stops has the catalog it had (the
  // simulator's and a real mill's all have some). A mill column of that
  // name is the mill's: the derived flag then stays out.
  const std::vector<unsigned char> after_stop = PassesAfterStop(data);
  const bool taken = std::any_of(
      c.begin(), c.end(),
      [](const CovariateSpec& s) { return s.name == kAfterStopName; });
  if (!taken &&
      std::find(after_stop.begin(), after_stop.end(), 1) != after_stop.end()) {
    c.push_back({kAfterStopName,
                 S::kAfterStop,
                 L::kPass,
                 K::kFlag,
                 -1,
                 false,
                 {},
                 /*locate_only=*/true});
  }
  // Last, so that adding it moved no other covariate's index.
  std::vector<std::string> rolls;
  for (const Mount& m : data.mounts) {
    if (!m.roll_id.empty()) rolls.push_back(m.roll_id);
  }
  std::sort(rolls.begin(), rolls.end());
  rolls.erase(std::unique(rolls.begin(), rolls.end()), rolls.end());
  if (rolls.size() >= 2) {
    c.push_back({kRollIdName, S::kRollId, L::kRoll, K::kFactor, -1, false,
                 std::move(rolls), /*locate_only=*/true});
  }
  return c;
}

double CovariateValue(const CovariateSpec& spec, const Dataset& data,
                      const PassContext& ctx, UnixSeconds origin) {
  // No pass (a reading after the campaign) or no mount: no value for them.
  static const Pass kNoPass;
  static const Mount kNoMount;
  if ((ctx.pass == nullptr && spec.level == CovariateLevel::kPass) ||
      (ctx.mount == nullptr && spec.level == CovariateLevel::kRoll)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const Pass& p = ctx.pass != nullptr ? *ctx.pass : kNoPass;
  const Mount& m = ctx.mount != nullptr ? *ctx.mount : kNoMount;
  switch (spec.source) {
    case CovariateSource::kForce:
      return p.force_kn;
    case CovariateSource::kWidth:
      return p.width_mm;
    case CovariateSource::kLength:
      return p.length_m;
    case CovariateSource::kEntryThickness:
      return p.entry_thickness_mm;
    case CovariateSource::kExitThickness:
      return p.exit_thickness_mm;
    case CovariateSource::kTemperature:
      return p.temperature_c;
    case CovariateSource::kSpeed:
      return p.speed_mps;
    case CovariateSource::kLubrication:
      return p.lubrication ? 1.0 : 0.0;
    case CovariateSource::kShift:
      return p.shift_mm;
    case CovariateSource::kSpecificForce:
      return SpecificForce(p);
    case CovariateSource::kContactLength:
      return ContactLength(p, m.diameter_mm);
    case CovariateSource::kReduction:
      return Reduction(p);
    case CovariateSource::kLengthBefore:
      return ctx.length_before_m;
    case CovariateSource::kCoilsBefore:
      return ctx.coils_before;
    case CovariateSource::kHoursSinceMount:
      return static_cast<double>(p.rolled_at - ctx.campaign->started_at) /
             3600.0;
    case CovariateSource::kDiameter:
      return m.diameter_mm;
    case CovariateSource::kHardness:
      return m.hardness_hb;
    case CovariateSource::kStartedAt:
      return static_cast<double>(ctx.campaign->started_at - origin) / 86400.0;
    case CovariateSource::kMeasuredAt:
      if (ctx.measurement_row < 0) return kNaN;
      return static_cast<double>(
                 data.measurements[ctx.measurement_row].measured_at - origin) /
             86400.0;
    case CovariateSource::kCell:
      return 1.0;
    case CovariateSource::kRollCampaignsBefore:
      return ctx.roll_campaigns_before;
    case CovariateSource::kAfterStop:
      return ctx.after_stop;
    case CovariateSource::kRollId: return SortedLevelIndex(spec.levels, m.roll_id);
    case CovariateSource::kCoolingHours:
      if (ctx.measurement_row < 0) return kNaN;
      return CoolingHours(data.measurements[ctx.measurement_row].measured_at,
                          ctx.campaign->ended_at);
    case CovariateSource::kPassExtraNumeric:
      return data.pass_extra.numeric[spec.extra_column][ctx.pass_row];
    case CovariateSource::kMountExtraNumeric:
      return data.mount_extra.numeric[spec.extra_column][ctx.mount_row];
    case CovariateSource::kCampaignExtraNumeric:
      return data.campaign_extra.numeric[spec.extra_column][ctx.campaign_row];
    case CovariateSource::kMeasurementExtraNumeric:
      if (ctx.measurement_row < 0) return kNaN;
      return data.measurement_extra
          .numeric[spec.extra_column][ctx.measurement_row];
    case CovariateSource::kPassExtraFactor:
      return data.pass_extra.factor[spec.extra_column][ctx.pass_row];
    case CovariateSource::kMountExtraFactor:
      return data.mount_extra.factor[spec.extra_column][ctx.mount_row];
    case CovariateSource::kCampaignExtraFactor:
      return data.campaign_extra.factor[spec.extra_column][ctx.campaign_row];
    case CovariateSource::kMeasurementExtraFactor:
      if (ctx.measurement_row < 0) return kNaN;
      return data.measurement_extra
          .factor[spec.extra_column][ctx.measurement_row];
  }
  return kNaN;
}

std::vector<int> RollCampaignsBefore(const Dataset& data) {
  std::vector<int> order(data.mounts.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  const auto started = [&](int row) {
    const int c = data.mounts[row].campaign;
    return c >= 0 && c < static_cast<int>(data.campaigns.size())
               ? data.campaigns[c].started_at
               : UnixSeconds{0};
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return started(a) < started(b); });
  // Counted per roll over distinct campaigns: a roll listed twice in one
  // campaign (a data error the import rejects) counts once.
  std::unordered_map<std::string, std::pair<int, int>>
      seen;  // id -> (count, last campaign)
  std::vector<int> out(data.mounts.size(), 0);
  for (int row : order) {
    const Mount& m = data.mounts[row];
    auto [it, fresh] = seen.try_emplace(m.roll_id, 0, -1);
    if (!fresh && it->second.second != m.campaign) {
      ++it->second.first;
      it->second.second = m.campaign;
    } else if (fresh) {
      it->second.second = m.campaign;
    }
    out[row] = it->second.first;
  }
  return out;
}

std::vector<unsigned char> PassesAfterStop(const Dataset& data) {
  std::vector<unsigned char> out(data.passes.size(), 0);
  if (data.passes.empty()) return out;
  const DatasetIndex index(data);
  std::vector<double> spacing;
  const auto each_sequence = [&](const auto& visit) {
    for (size_t c = 0; c < data.campaigns.size(); ++c) {
      for (int stand = 0; stand <= kMaxStand; ++stand) {
        const std::vector<int>& rows =
            index.PassesOf(static_cast<int>(c), stand);
        if (rows.size() >= 2) visit(rows);
      }
    }
  };
  each_sequence([&](const std::vector<int>& rows) {
    for (size_t i = 1; i < rows.size(); ++i) {
      spacing.push_back(static_cast<double>(
          data.passes[rows[i]].rolled_at - data.passes[rows[i - 1]].rolled_at));
    }
  });
  if (spacing.empty()) return out;
  const auto mid =
      spacing.begin() + static_cast<std::ptrdiff_t>(spacing.size() / 2);
  std::nth_element(spacing.begin(), mid, spacing.end());
  const double stop_s = std::max(kStopMinSpacingS, kStopSpacingRatio * *mid);
  each_sequence([&](const std::vector<int>& rows) {
    int since = -1;  // coils since the last stop; -1: none yet
    // The gap from the latest coil so far: a rolled_at out of seq order
    // makes no stop of the coil after it.
    UnixSeconds latest = data.passes[rows[0]].rolled_at;
    for (size_t i = 1; i < rows.size(); ++i) {
      const UnixSeconds at = data.passes[rows[i]].rolled_at;
      const double gap = static_cast<double>(at - latest);
      latest = std::max(latest, at);
      if (gap > stop_s) {
        since = 0;
      } else if (since >= 0) {
        ++since;
      }
      if (since >= 0 && since < kAfterStopCoils) out[rows[i]] = 1;
    }
  });
  return out;
}

}  // namespace rollwear
