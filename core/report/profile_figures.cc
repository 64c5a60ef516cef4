#include "core/report/profile_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

#include "core/fit/profile_fit.h"
#include "core/report/svg_plot.h"

namespace rollwear {

StatusOr<SvgFigure> ProfileFigure(const std::string& title,
                                  const WearModel& model,
                                  const ProfileShape& shape,
                                  const Dataset& data,
                                  const CampaignSplit& split, int max_panels) {
  const DatasetIndex index(data);
  std::vector<int> val = split.validation;
  std::sort(val.begin(), val.end());
  // The validation rolls with profiles, in (campaign, slot) order.
  std::map<std::pair<int, int>, std::vector<int>> rolls =
      ProfilePointsByRoll(data);
  std::erase_if(rolls, [&](const auto& roll) {
    return !std::binary_search(val.begin(), val.end(), roll.first.first);
  });
  if (rolls.empty()) {
    return Status::FailedPrecondition(
        "no validation roll has a profile to draw");
  }
  const int n = std::min<int>(max_panels, static_cast<int>(rolls.size()));
  std::vector<PlotSpec> panels;
  auto it = rolls.begin();
  int at = 0;
  for (int k = 0; k < n; ++k) {
    const int want = static_cast<int>(k * rolls.size() / n);
    std::advance(it, want - at);
    at = want;
    const auto [campaign, slot] = it->first;
    const ProfileFitOptions options;
    const std::vector<double> predicted = PredictRollProfile(
        model, shape, data, index, campaign, slot, options);
    PlotSeries measured =
        PlotSeries::Make("measured", PaletteColor(0), PlotSeries::Style::kPoints);
    measured.radius = 1.5;
    double lo = 1e300, hi = -1e300, gap = 0;
    for (int i : it->second) {
      const ProfilePoint& p = data.profile_points[i];
      measured.x.push_back(p.x_mm);
      measured.y.push_back(p.wear_um);
      lo = std::min(lo, p.x_mm);
      hi = std::max(hi, p.x_mm);
      gap += std::abs(p.wear_um - options.grid.Interpolate(predicted, p.x_mm));
    }
    gap /= static_cast<double>(it->second.size());
    PlotSeries line =
        PlotSeries::Make("predicted", PaletteColor(1), PlotSeries::Style::kLine);
    for (int j = 0; j < options.grid.slices(); ++j) {
      const double x = options.grid.x(j);
      if (x < lo || x > hi) continue;
      line.x.push_back(x);
      line.y.push_back(predicted[j]);
    }
    const Mount& mount = data.mounts[index.MountOf(campaign, slot)];
    char name[160];
    std::snprintf(name, sizeof(name), "%s %s: gap %.1f µm",
                  data.campaigns[campaign].id.c_str(),
                  RollPositionName(mount.stand, mount.position).c_str(), gap);
    PlotSpec spec;
    spec.title = name;
    spec.x_label = "x from barrel centre (mm)";
    spec.y_label = "wear (µm)";
    spec.series = {std::move(measured), std::move(line)};
    spec.legend = k == 0 ? PlotSpec::Legend::kTopRight : PlotSpec::Legend::kNone;
    panels.push_back(std::move(spec));
  }
  return SvgFigure{kProfileFigureName, RenderSvgGrid(title, panels, 3)};
}

}  // namespace rollwear
