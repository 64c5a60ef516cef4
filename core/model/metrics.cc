#include "core/model/metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/base/random.h"

namespace rollwear {

CampaignSplit SplitCampaigns(const WearStatistics& stats, double train_fraction,
                             uint64_t seed) {
  std::vector<int> measured;
  for (const Observation& o : stats.observations) {
    if (o.measurement >= 0 &&
        (measured.empty() || measured.back() != o.campaign)) {
      measured.push_back(o.campaign);
    }
  }
  measured.erase(std::unique(measured.begin(), measured.end()), measured.end());
  Random rng(seed);
  rng.Shuffle(&measured);
  const size_t n_train = static_cast<size_t>(
      std::lround(train_fraction * static_cast<double>(measured.size())));
  CampaignSplit split;
  split.train.assign(measured.begin(), measured.begin() + n_train);
  split.validation.assign(measured.begin() + n_train, measured.end());
  std::sort(split.train.begin(), split.train.end());
  std::sort(split.validation.begin(), split.validation.end());
  return split;
}

CampaignSplit SplitOrGiven(const WearStatistics& stats, uint64_t seed,
                           const std::optional<CampaignSplit>& given) {
  return given ? *given : SplitCampaigns(stats, 2.0 / 3.0, seed);
}

std::vector<double> PredictAll(const WearModel& model,
                               const WearStatistics& stats,
                               const std::vector<int>& obs) {
  std::vector<double> out;
  out.reserve(obs.size());
  for (int i : obs) out.push_back(PredictObservation(model, stats, stats.observations[i]));
  return out;
}

double PaperCost(const std::vector<int>& position,
                 const std::vector<double>& measured,
                 const std::vector<double>& predicted) {
  std::map<int, std::pair<double, int>> per_position;
  for (size_t i = 0; i < measured.size(); ++i) {
    const double d = measured[i] - predicted[i];
    auto& [sum, n] = per_position[position[i]];
    sum += d * d;
    ++n;
  }
  double cost = 0;
  for (const auto& [p, sn] : per_position) cost += sn.first / sn.second;
  return cost;
}

FitMetrics MetricsOf(const std::vector<int>& position, const std::vector<double>& measured,
                     const std::vector<double>& predicted) {
  FitMetrics m;
  m.n = static_cast<int>(measured.size());
  if (measured.empty()) return m;
  double abs_sum = 0;
  for (size_t i = 0; i < measured.size(); ++i) abs_sum += std::abs(measured[i] - predicted[i]);
  m.gap_um = abs_sum / static_cast<double>(measured.size());
  m.cost = PaperCost(position, measured, predicted);
  return m;
}

FitMetrics Evaluate(const WearModel& model, const WearStatistics& stats,
                    const std::vector<int>& obs) {
  std::vector<double> measured;
  std::vector<int> position;
  for (int i : obs) {
    measured.push_back(stats.observations[i].measured_um);
    position.push_back(stats.observations[i].position);
  }
  const std::vector<double> predicted = PredictAll(model, stats, obs);
  FitMetrics m = MetricsOf(position, measured, predicted);
  if (model.noise_sd_um > 0 || model.noise_rel > 0) {
    double sum = 0;
    for (size_t i = 0; i < predicted.size(); ++i) {
      const double sd = std::hypot(model.noise_sd_um, model.noise_rel * predicted[i]);
      sum += std::abs(measured[i] - predicted[i]) / sd;
    }
    if (!predicted.empty()) m.std_gap = sum / static_cast<double>(predicted.size());
  }
  return m;
}

}  // namespace rollwear
