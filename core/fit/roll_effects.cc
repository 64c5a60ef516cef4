#include "core/fit/roll_effects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace rollwear {
namespace {

constexpr int kMaxRounds = 100;
constexpr double kTolerance = 1e-3;

// One training reading: the law's prediction x, the reading y.
struct Reading {
  double x = 0, y = 0;
};

// The noise model var(e) = a + b x^2 of the within-roll residuals e = y -
// mhat_r x (least squares of e^2 on [1, x^2], each part kept >= 0, scaled
// by n / (n - R) for the R multipliers fitted): grinder noise plus a part
// that grows with the wear (the campaign-to-campaign scatter of a roll).
struct NoiseModel {
  double a = 1, b = 0;
  double VarAt(double x) const { return a + b * x * x; }
};

// Per roll: mhat_r and sum w x^2 (= 1 / v_r) under weights w = 1 / var(x).
struct RollFit {
  double mhat = 1, info = 0;
  int n = 0;
};

RollFit FitRoll(const std::vector<Reading>& readings, const NoiseModel& noise) {
  RollFit f;
  double sxy = 0;
  for (const Reading& r : readings) {
    const double w = 1 / noise.VarAt(r.x);
    f.info += w * r.x * r.x;
    sxy += w * r.x * r.y;
  }
  f.n = static_cast<int>(readings.size());
  if (f.info > 0) f.mhat = sxy / f.info;
  return f;
}

NoiseModel FitNoise(const std::map<std::string, std::vector<Reading>>& rolls,
                    const std::map<std::string, RollFit>& fits) {
  // Normal equations of e^2 = a + b x^2.
  double s11 = 0, s12 = 0, s22 = 0, t1 = 0, t2 = 0;
  int n = 0, r_count = 0;
  for (const auto& [id, readings] : rolls) {
    const RollFit& f = fits.at(id);
    if (!(f.info > 0)) continue;
    ++r_count;
    for (const Reading& r : readings) {
      const double e = r.y - f.mhat * r.x, x2 = r.x * r.x;
      s11 += 1;
      s12 += x2;
      s22 += x2 * x2;
      t1 += e * e;
      t2 += x2 * e * e;
      ++n;
    }
  }
  NoiseModel m;
  if (n <= r_count) return m;
  const double det = s11 * s22 - s12 * s12;
  if (det > 0) {
    m.a = (t1 * s22 - t2 * s12) / det;
    m.b = (s11 * t2 - s12 * t1) / det;
  }
  if (!(m.b > 0)) {
    m = {t1 / s11, 0};  // constant noise only
  } else if (!(m.a > 0)) {
    m = {0, t2 / s22};  // relative noise only
  }
  const double df = static_cast<double>(n) / (n - r_count);
  m.a = std::max(m.a * df, 1e-6);
  m.b *= df;
  return m;
}

// One empirical-Bayes step (the header's formulas): the multipliers given
// the law's predictions x of the training readings.
// With `estimate`, the noise model is first fitted (three passes of
// weights and noise) and left in *noise; otherwise *noise is used as is.
RollEffects Shrink(const std::map<std::string, std::vector<Reading>>& rolls,
                   const std::map<std::string, std::string>& group_of,
                   bool estimate, NoiseModel* noise_model) {
  RollEffects e;
  std::map<std::string, RollFit> fits;
  NoiseModel& noise = *noise_model;
  for (int pass = 0; estimate && pass < 3; ++pass) {  // weights <-> noise
    for (const auto& [id, readings] : rolls)
      fits[id] = FitRoll(readings, noise);
    noise = FitNoise(rolls, fits);
  }
  for (const auto& [id, readings] : rolls) fits[id] = FitRoll(readings, noise);
  e.sigma_um = std::sqrt(noise.a);
  e.noise_rel = std::sqrt(noise.b);
  // Each group's weighted mean multiplier is the prior's centre for its
  // rolls: K carries the level of a roll type at a stand (kF, kR), so the
  // mean of its rolls' multipliers is not identified apart from it; every
  // multiplier is divided by its group's mean below and the next K absorbs
  // it (without this the backfitting drifts between the two).
  std::map<std::string, std::array<double, 3>> group;  // sw, swm, count
  for (const auto& [id, f] : fits) {
    if (!(f.info > 0)) continue;
    auto& g = group[group_of.at(id)];
    g[0] += f.info;
    g[1] += f.info * f.mhat;
    g[2] += 1;
  }
  auto mean_of = [&](const std::string& id) {
    auto it = group.find(group_of.at(id));
    return it == group.end() || !(it->second[0] > 0)
               ? 1.0
               : it->second[1] / it->second[0];
  };
  // DerSimonian-Laird with one mean per group: Q about the group means on
  // R - G degrees of freedom, and the weights' moment term per group.
  double q = 0, denominator = 0;
  int count = 0;
  for (const auto& [id, f] : fits) {
    if (!(f.info > 0)) continue;
    const double d = f.mhat - mean_of(id);
    q += f.info * d * d;
    ++count;
  }
  for (const auto& [key, g] : group) {
    double sw2 = 0;
    for (const auto& [id, f] : fits) {
      if (f.info > 0 && group_of.at(id) == key) sw2 += f.info * f.info;
    }
    denominator += g[0] - sw2 / g[0];
  }
  const int df = count - static_cast<int>(group.size());
  double tau2 = 0;  // relative to the group's mean
  if (df > 0 && denominator > 0) tau2 = std::max(0.0, (q - df) / denominator);
  e.tau = 0;
  // The variance of each group's centre, 1 / sum 1 / (v_r + tau^2): the
  // posterior sd of a roll adds it in proportion to how far the roll is
  // shrunk (Morris 1983, the estimated-mean correction).
  std::map<std::string, double> centre_info;
  for (const auto& [id, f] : fits) {
    if (f.info > 0 && tau2 > 0)
      centre_info[group_of.at(id)] += 1 / (1 / f.info + tau2);
  }
  double tau_sum = 0;
  for (const auto& [id, f] : fits) {
    RollEffect r;
    r.roll_id = id;
    r.readings = f.n;
    const double mbar = mean_of(id);
    if (f.info > 0 && tau2 > 0) {
      const double precision = f.info + 1 / tau2;
      r.value = (f.mhat * f.info + mbar / tau2) / precision / mbar;
      r.raw = f.mhat / mbar;
      const double shrink = (1 / tau2) / precision;
      r.sd = std::sqrt(1 / precision +
                       shrink * shrink / centre_info[group_of.at(id)]) /
             mbar;
      e.effective_parameters += f.info / precision;
    } else {
      r.raw = f.info > 0 ? f.mhat / mbar : 1;
      r.value = 1;
      r.sd = 0;
    }
    tau_sum += std::sqrt(tau2) / mbar;
    e.index[id] = static_cast<int>(e.rolls.size());
    e.rolls.push_back(r);
  }
  e.tau = fits.empty() ? 0 : tau_sum / static_cast<double>(fits.size());
  for (RollEffect& r : e.rolls) {
    if (r.sd == 0) r.sd = e.tau;
  }
  return e;
}

// A roll's group: its roll type at the stand of most of its training
// readings ("unknown@F6"); the prior centre of its multiplier.
std::map<std::string, std::string> RollGroups(const Dataset& data,
                                              const WearStatistics& stats,
                                              const std::vector<int>& train) {
  std::map<std::string, std::map<std::string, int>> count;
  for (int o : train) {
    const Mount& m = data.mounts[stats.observations[o].mount];
    ++count[m.roll_id][data.roll_types[m.roll_type] + "@" + StandName(m.stand)];
  }
  std::map<std::string, std::string> group;
  for (const auto& [id, c] : count) {
    group[id] =
        std::max_element(c.begin(), c.end(), [](const auto& a, const auto& b) {
          return a.second < b.second;
        })->first;
  }
  return group;
}

std::vector<double> Multipliers(const Dataset& data,
                                const WearStatistics& stats,
                                const RollEffects& e) {
  std::vector<double> m(stats.observations.size(), 1.0);
  for (size_t o = 0; o < m.size(); ++o) {
    m[o] = e.ValueOf(data.mounts[stats.observations[o].mount].roll_id);
  }
  return m;
}

FitMetrics Metrics(const WearModel& model, const WearStatistics& stats,
                   const std::vector<int>& obs,
                   const std::vector<double>& mult) {
  std::vector<double> measured, predicted;
  std::vector<int> position;
  for (int o : obs) {
    const Observation& ob = stats.observations[o];
    measured.push_back(ob.measured_um);
    position.push_back(ob.position);
    predicted.push_back(mult[o] * PredictObservation(model, stats, ob));
  }
  return MetricsOf(position, measured, predicted);
}

}  // namespace

double RollEffects::ValueOf(const std::string& roll_id) const {
  auto it = index.find(roll_id);
  return it == index.end() ? 1.0 : rolls[it->second].value;
}

double RollEffects::SdOf(const std::string& roll_id) const {
  auto it = index.find(roll_id);
  return it == index.end() ? tau : rolls[it->second].sd;
}

WearStatistics ScaledStatistics(const WearStatistics& stats,
                                const std::vector<double>& multiplier) {
  WearStatistics s = stats;
  for (size_t o = 0; o < s.observations.size(); ++o) {
    for (CellLoad& cell : s.observations[o].cells) {
      cell.load *= multiplier[o];
      for (int i = cell.pass_begin; i < cell.pass_end; ++i) {
        s.cao_base[i] *= multiplier[o];
      }
    }
  }
  return s;
}

StatusOr<RollEffectsFit> CalibrateWithRollEffects(
    const Dataset& data, const WearStatistics& stats,
    const CampaignSplit& split, const CalibrationOptions& options) {
  const std::vector<int> train = stats.MeasuredObservations(split.train);
  const std::vector<int> val = stats.MeasuredObservations(split.validation);
  RollEffectsFit fit;
  fit.multiplier.assign(stats.observations.size(), 1.0);
  NoiseModel noise;
  for (int round = 1; round <= kMaxRounds; ++round) {
    ROLLWEAR_ASSIGN_OR_RETURN(
        fit.result,
        Calibrate(ScaledStatistics(stats, fit.multiplier), train, options));
    std::map<std::string, std::vector<Reading>> rolls;
    for (int o : train) {
      const Observation& ob = stats.observations[o];
      rolls[data.mounts[ob.mount].roll_id].push_back(
          {PredictObservation(fit.result.model, stats, ob), ob.measured_um});
    }
    const std::map<std::string, std::string> group_of =
        RollGroups(data, stats, train);
    // The noise model of the first round (K alone) is kept: re-estimating
    // it every round let the alternation oscillate on simulated mills.
    fit.effects = Shrink(rolls, group_of, round == 1, &noise);
    fit.effects.iterations = round;
    const std::vector<double> next = Multipliers(data, stats, fit.effects);
    double moved = 0;
    for (size_t o = 0; o < next.size(); ++o) {
      moved = std::max(moved, std::abs(next[o] - fit.multiplier[o]));
    }
    fit.multiplier = next;
    if (moved < kTolerance) {
      fit.effects.converged = true;
      break;
    }
  }
  // K for the final multipliers.
  ROLLWEAR_ASSIGN_OR_RETURN(
      fit.result,
      Calibrate(ScaledStatistics(stats, fit.multiplier), train, options));
  fit.train = Metrics(fit.result.model, stats, train, fit.multiplier);
  fit.validation = Metrics(fit.result.model, stats, val, fit.multiplier);
  return fit;
}

}  // namespace rollwear
