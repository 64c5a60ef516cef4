// Does what is left behave like measurement noise? The checks a fitted
// noise model hides (docs/diagnosis.md, "Noise checks"), run on the final
// model's residuals u_i = (measured - predicted) / sd_i, standardised by the
// robust noise model (robust.h) and clipped to +-kHuberK (Huber's psi):
//  - time_scale_S: campaign means of u in time order (started_at), cut into
//    S consecutive blocks, S = 2, 4, 8 ... while each block holds >= 8
//    campaigns; one-way ANOVA F over the blocks. Catches drifts and level
//    shifts at every scale the data supports.
//  - lag1_along_time: lag-1 autocorrelation r1 of those campaign means;
//    under independence r1 ~ N(-1/n, 1/n) approximately (Bartlett 1946,
//    J. R. Stat. Soc. Suppl. 8:27; Box, Jenkins & Reinsel, "Time Series
//    Analysis", 4th ed., 2008, sec. 2.1.6); z = (r1 + 1/n) sqrt(n).
//  - runs_along_time: Wald-Wolfowitz runs test on the signs of the campaign
//    means (Wald & Wolfowitz 1940, Ann. Math. Stat. 11:147): with n1
//    positive, n2 negative, n = n1 + n2 and R runs,
//    E[R] = 2 n1 n2 / n + 1, Var[R] = 2 n1 n2 (2 n1 n2 - n) / (n^2 (n - 1)),
//    z = (R - E[R]) / sqrt(Var[R]) ~ N(0, 1).
//  - position_by_time_half: ANOVA of u over roll position x half of the
//    time range (a position that wears differently in one period only).
//  - position_by_roll_type: ANOVA of u over roll position x roll type
//    cells (a roll type that wears differently at one stand only), and
//    position_by_grade over roll position x dominant grade cells.
//  - spread_by_position, spread_by_time (calendar quarters) and
//    spread_time_scale_S (S blocks of campaigns in time order, as
//    time_scale_S): Brown-Forsythe test of equal spread (Brown & Forsythe
//    1974, JASA 69:364): one-way ANOVA F of d_i = |u_i - median of u in
//    i's group| over the groups.
// Then every breakdown (Locate's and these) significant at the family-wise
// level (Bonferroni over all of them) and of material size becomes an
// Unexplained entry.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <string>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_internal.h"
#include "core/fit/robust.h"

namespace rollwear::diag {
namespace {

double NormalTwoSided(double z) {
  return std::erfc(std::abs(z) / std::sqrt(2.0));
}

std::string Ordinal(int i) {  // 1-based
  const char* suffix = (i % 100 >= 11 && i % 100 <= 13) ? "th"
                       : i % 10 == 1                    ? "st"
                       : i % 10 == 2                    ? "nd"
                       : i % 10 == 3                    ? "rd"
                                                        : "th";
  return std::to_string(i) + suffix;
}

// ANOVA of the standardised values `u` (the test) with the µm group means
// of `um` (the size); groups in the order of `order`.
Breakdown AnovaWithSize(const std::string& dimension,
                        const std::vector<std::string>& label,
                        const std::vector<double>& u,
                        const std::vector<double>& um,
                        const std::vector<std::string>& order = {}) {
  const std::vector<double> zero(u.size(), 0.0);
  Breakdown b = AnovaBreakdown(dimension, label, u, zero, order);
  const Breakdown size = AnovaBreakdown(dimension, label, um, zero, order);
  for (size_t g = 0; g < b.groups.size(); ++g) {  // the test's t, the µm size
    b.groups[g].mean_residual_um = size.groups[g].mean_residual_um;
  }
  b.effect_size = 0;
  for (const Breakdown::Group& g : b.groups) {
    b.effect_size = std::max(b.effect_size, std::abs(g.mean_residual_um));
  }
  return b;
}

// The labels of `blocks` consecutive blocks of n campaigns in time order,
// campaign i (0-based) in block i * blocks / n: block b holds campaigns
// ceil(b n / blocks) .. ceil((b + 1) n / blocks) - 1, printed 1-based.
std::vector<std::string> BlockLabels(int n, int blocks) {
  std::vector<std::string> order;
  for (int b = 0; b < blocks; ++b) {
    const int first = (b * n + blocks - 1) / blocks;
    const int last = ((b + 1) * n + blocks - 1) / blocks - 1;
    order.push_back("block " + Ordinal(b + 1) + " of " +
                    std::to_string(blocks) + " (campaigns " +
                    std::to_string(first + 1) + "-" + std::to_string(last + 1) +
                    " in time order)");
  }
  return order;
}

void TimeChecks(const CampaignSeries& s, const DiagnosisThresholds& thresholds,
                std::vector<Breakdown>* out) {
  const int n = static_cast<int>(s.u.size());
  if (n < 2 * thresholds.min_campaigns_per_block) return;
  for (int blocks = 2; n / blocks >= thresholds.min_campaigns_per_block;
       blocks *= 2) {
    std::vector<std::string> label(n);
    const std::vector<std::string> order = BlockLabels(n, blocks);
    for (int i = 0; i < n; ++i)
      label[i] = order[static_cast<size_t>(i) * blocks / n];
    out->push_back(AnovaWithSize("time_scale_" + std::to_string(blocks), label,
                                 s.u, s.um, order));
  }
  double rms_um = 0;
  for (double v : s.um) rms_um += v * v;
  rms_um = std::sqrt(rms_um / n);
  // Lag-1 autocorrelation.
  const double mean = std::accumulate(s.u.begin(), s.u.end(), 0.0) / n;
  double c0 = 0, c1 = 0;
  for (int i = 0; i < n; ++i) c0 += (s.u[i] - mean) * (s.u[i] - mean);
  for (int i = 0; i + 1 < n; ++i) c1 += (s.u[i] - mean) * (s.u[i + 1] - mean);
  if (c0 > 0) {
    Breakdown b;
    b.dimension = "lag1_along_time";
    b.test = "lag1_autocorrelation";
    const double r1 = c1 / c0;
    b.statistic = (r1 + 1.0 / n) * std::sqrt(static_cast<double>(n));
    b.p_value = NormalTwoSided(b.statistic);
    b.effect_size = std::abs(r1);
    char buf[96];
    std::snprintf(buf, sizeof(buf),
                  "campaign order (lag-1 autocorrelation %+.2f)", r1);
    b.groups.push_back({buf, n, rms_um, 0});
    out->push_back(b);
  }
  // Wald-Wolfowitz runs of signs.
  int n1 = 0, n2 = 0, runs = 0, last = 0;
  for (double v : s.u) {
    if (v == 0) continue;
    const int sign = v > 0 ? 1 : -1;
    (sign > 0 ? n1 : n2)++;
    if (sign != last) ++runs;
    last = sign;
  }
  const double nn = n1 + n2;
  if (n1 > 0 && n2 > 0 && nn > 2) {
    const double e = 2.0 * n1 * n2 / nn + 1;
    const double var =
        2.0 * n1 * n2 * (2.0 * n1 * n2 - nn) / (nn * nn * (nn - 1));
    Breakdown b;
    b.dimension = "runs_along_time";
    b.test = "runs";
    b.statistic = var > 0 ? (runs - e) / std::sqrt(var) : 0;
    b.p_value = var > 0 ? NormalTwoSided(b.statistic) : 1;
    b.effect_size = std::abs(runs - e) / e;
    char buf[128];
    std::snprintf(
        buf, sizeof(buf),
        "campaign order (%d runs of same-signed campaign means, %.0f expected)",
        runs, e);
    b.groups.push_back({buf, n, rms_um, 0});
    out->push_back(b);
  }
}

// The Brown-Forsythe breakdown from the deviations `d` (|u - group
// median|) and their µm sizes `d_um` (|residual|), one value per unit
// (a reading, or a campaign's mean): ANOVA of d over the groups; effect
// size and group "mean" = the group's mean d relative to the overall one,
// minus 1 (the µm size is carried in mean_residual_um).
Breakdown SpreadOfDeviations(const std::string& dimension,
                             const std::vector<std::string>& label,
                             const std::vector<double>& d,
                             const std::vector<double>& d_um) {
  double overall = 0;
  for (double v : d) overall += v;
  overall /= std::max<size_t>(1, d.size());
  const std::vector<double> zero(d.size(), 0.0);
  Breakdown b = AnovaBreakdown(dimension, label, d, zero);
  b.test = "brown_forsythe";
  const Breakdown size = AnovaBreakdown(dimension, label, d_um, zero);
  b.effect_size = 0;
  for (size_t g = 0; g < b.groups.size(); ++g) {
    // mean_relative: spread ratio - 1; mean_residual_um: mean |residual|.
    b.groups[g].mean_relative =
        overall > 0 ? b.groups[g].mean_residual_um / overall - 1 : 0;
    b.groups[g].mean_residual_um = size.groups[g].mean_residual_um;
    b.effect_size =
        std::max(b.effect_size, std::abs(b.groups[g].mean_relative));
  }
  return b;
}

// |u_i - median of u in i's group| (Brown & Forsythe 1974).
std::vector<double> DeviationsFromGroupMedian(
    const std::vector<std::string>& label, const std::vector<double>& u) {
  std::map<std::string, std::vector<double>> by;
  for (size_t i = 0; i < u.size(); ++i) by[label[i]].push_back(u[i]);
  std::map<std::string, double> median;
  for (auto& [k, v] : by) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    median[k] = v[v.size() / 2];
  }
  std::vector<double> d(u.size());
  for (size_t i = 0; i < u.size(); ++i) d[i] = std::abs(u[i] - median[label[i]]);
  return d;
}

// Brown-Forsythe over the readings.
Breakdown SpreadCheck(const std::string& dimension,
                      const std::vector<std::string>& label,
                      const std::vector<double>& u,
                      const std::vector<double>& um) {
  std::vector<double> d_um(um.size());
  for (size_t i = 0; i < um.size(); ++i) d_um[i] = std::abs(um[i]);
  return SpreadOfDeviations(dimension, label,
                            DeviationsFromGroupMedian(label, u), d_um);
}

bool Material(const Breakdown& b, double material_um,
              const DiagnosisThresholds& thresholds) {
  if (b.test == "lag1_autocorrelation")
    return b.effect_size >= thresholds.material_autocorrelation;
  if (b.test == "runs") return b.effect_size >= thresholds.material_runs_share;
  if (b.test == "brown_forsythe")
    return b.effect_size >= thresholds.material_spread_share;
  double largest = 0;
  for (const Breakdown::Group& g : b.groups) {
    largest = std::max(largest, std::abs(g.mean_residual_um));
  }
  return largest >= material_um;
}

std::string Where(const Breakdown& b, const Breakdown::Group& g) {
  if (b.dimension.rfind("time_scale_", 0) == 0)
    return "calendar time, " + g.label;
  if (b.test == "lag1_autocorrelation" || b.test == "runs") return g.label;
  if (b.test == "brown_forsythe") {
    char buf[48];
    std::snprintf(buf, sizeof(buf), " (spread %+.0f %%)",
                  100 * g.mean_relative);
    return (b.dimension == "spread_by_position" ? "roll_position="
                                                : "calendar time, ") +
           g.label + buf;
  }
  if (b.dimension.rfind("position_by_", 0) == 0)
    return "roll_position=" + g.label;
  return b.dimension + "=" + g.label;
}

}  // namespace

const Breakdown::Group* Carrier(const Breakdown& b) {
  const Breakdown::Group* best = nullptr;
  auto size = [&](const Breakdown::Group& g) {
    return b.test == "brown_forsythe" ? std::abs(g.mean_relative)
                                      : std::abs(g.mean_residual_um);
  };
  for (const Breakdown::Group& g : b.groups) {
    if (g.label == "missing") continue;
    if (best == nullptr || size(g) > size(*best)) best = &g;
  }
  return best;
}

CampaignSeries ByCampaignInTime(const TermData& td, const Dataset& data,
                                const std::vector<int>& obs,
                                const std::vector<double>& u,
                                const std::vector<double>& um) {
  std::map<int, std::pair<double, double>> sum;
  std::map<int, int> count;
  for (size_t i = 0; i < obs.size(); ++i) {
    const int c = td.obs[obs[i]].campaign;
    sum[c].first += u[i];
    sum[c].second += um[i];
    ++count[c];
  }
  std::vector<int> camps;
  for (const auto& [c, n] : count) camps.push_back(c);
  std::stable_sort(camps.begin(), camps.end(), [&](int a, int b) {
    return data.campaigns[a].started_at < data.campaigns[b].started_at;
  });
  CampaignSeries s;
  for (int c : camps) {
    s.u.push_back(sum[c].first / count[c]);
    s.um.push_back(sum[c].second / count[c]);
  }
  return s;
}

namespace {

// spread_time_scale_S: Brown-Forsythe over S consecutive blocks of
// campaigns in time order (S = 2, 4, 8 ... while each block holds
// thresholds.min_campaigns_per_block campaigns), the spread's counterpart of
// time_scale_S: a few periods of extra scatter (a bad batch of rolls, an
// unstable gauge for a month) are a small part of any calendar quarter but
// most of a block of their own length. The unit is the campaign, as in
// time_scale_S: its readings' mean deviation from their block's median,
// so that what the readings of one campaign share is not counted as
// independent evidence.
void SpreadAlongTime(const TermData& td, const Dataset& data,
                     const std::vector<int>& obs, const std::vector<double>& u,
                     const std::vector<double>& um,
                     const DiagnosisThresholds& thresholds,
                     std::vector<Breakdown>* out) {
  std::vector<int> camps;
  for (int o : obs) camps.push_back(td.obs[o].campaign);
  std::sort(camps.begin(), camps.end());
  camps.erase(std::unique(camps.begin(), camps.end()), camps.end());
  std::stable_sort(camps.begin(), camps.end(), [&](int a, int b) {
    return data.campaigns[a].started_at < data.campaigns[b].started_at;
  });
  std::map<int, int> rank;
  for (size_t r = 0; r < camps.size(); ++r)
    rank[camps[r]] = static_cast<int>(r);
  const int n = static_cast<int>(camps.size());
  for (int blocks = 2; n / blocks >= thresholds.min_campaigns_per_block;
       blocks *= 2) {
    const std::vector<std::string> order = BlockLabels(n, blocks);
    std::vector<std::string> label(obs.size());
    for (size_t i = 0; i < obs.size(); ++i) {
      label[i] = order[static_cast<size_t>(rank[td.obs[obs[i]].campaign]) *
                       blocks / n];
    }
    const std::vector<double> d = DeviationsFromGroupMedian(label, u);
    std::vector<double> d_c(n, 0.0), d_um_c(n, 0.0), count(n, 0.0);
    for (size_t i = 0; i < obs.size(); ++i) {
      const int r = rank[td.obs[obs[i]].campaign];
      d_c[r] += d[i];
      d_um_c[r] += std::abs(um[i]);
      count[r] += 1;
    }
    std::vector<std::string> label_c(n);
    for (int r = 0; r < n; ++r) {
      d_c[r] /= count[r];
      d_um_c[r] /= count[r];
      label_c[r] = order[static_cast<size_t>(r) * blocks / n];
    }
    out->push_back(SpreadOfDeviations(
        "spread_time_scale_" + std::to_string(blocks), label_c, d_c, d_um_c));
  }
}

}  // namespace

std::vector<Breakdown> NoiseChecks(const TermData& td, const Dataset& data,
                                   const std::vector<int>& obs,
                                   const std::vector<double>& pred,
                                   const std::vector<double>& sd,
                                   const DiagnosisThresholds& thresholds) {
  const size_t n = obs.size();
  std::vector<double> u(n), um(n);
  double t_min = 0, t_max = 0;
  for (size_t i = 0; i < n; ++i) {
    const double e = td.obs[obs[i]].measured_um - pred[i];
    u[i] = std::clamp(e / sd[i], -kHuberK, kHuberK);
    um[i] = u[i] * sd[i];
    const double t =
        static_cast<double>(data.campaigns[td.obs[obs[i]].campaign].started_at);
    t_min = i == 0 ? t : std::min(t_min, t);
    t_max = i == 0 ? t : std::max(t_max, t);
  }
  std::vector<Breakdown> out;
  TimeChecks(ByCampaignInTime(td, data, obs, u, um), thresholds, &out);
  // Position x half of the time range; position and time quarters spread.
  std::vector<std::string> pos_half(n), pos_type(n), pos_grade(n), position(n),
      quarter(n);
  std::vector<std::string> q_order;
  for (int q = 0; q < 4; ++q) q_order.push_back(Ordinal(q + 1) + " quarter");
  for (size_t i = 0; i < n; ++i) {
    const TermObservation& o = td.obs[obs[i]];
    const double t = static_cast<double>(data.campaigns[o.campaign].started_at);
    const double share = t_max > t_min ? (t - t_min) / (t_max - t_min) : 0;
    position[i] = td.positions[o.position];
    pos_half[i] = position[i] + ", calendar time " +
                  (share < 0.5 ? "1st half" : "2nd half");
    pos_type[i] = position[i] + ", roll_type=" +
                  (o.roll_type >= 0 ? td.roll_types[o.roll_type] : "?");
    pos_grade[i] = position[i] + ", dominant_grade=" + DominantGrade(td, o);
    quarter[i] = q_order[std::min(3, static_cast<int>(4 * share))];
  }
  out.push_back(AnovaWithSize("position_by_time_half", pos_half, u, um));
  out.push_back(AnovaWithSize("position_by_roll_type", pos_type, u, um));
  out.push_back(AnovaWithSize("position_by_grade", pos_grade, u, um));
  out.push_back(SpreadCheck("spread_by_position", position, u, um));
  out.push_back(SpreadCheck("spread_by_time", quarter, u, um));
  SpreadAlongTime(td, data, obs, u, um, thresholds, &out);
  GradeByCampaignOrder(td, obs, u, um, thresholds, &out);
  return out;
}

std::vector<Unexplained> UnexplainedStructure(
    const std::vector<Breakdown>& checks, double alpha, double material_um,
    const DiagnosisThresholds& thresholds) {
  std::vector<Unexplained> out;
  const double m = static_cast<double>(checks.size());
  for (const Breakdown& b : checks) {
    const double p_adj = std::min(1.0, b.p_value * m);
    if (!(p_adj < alpha) || !Material(b, material_um, thresholds)) continue;
    auto add = [&](const Breakdown::Group& g, double p, double p_adjusted) {
      out.push_back({b.dimension, Where(b, g), b.test, b.statistic,
                     g.mean_residual_um, p, p_adjusted});
    };
    // ANOVA: every group whose own mean is significantly off zero (t test,
    // Bonferroni over the groups and the checks) and material; else the
    // group that carries the structure.
    int listed = 0;
    if (b.test == "anova") {
      const double groups = static_cast<double>(b.groups.size());
      int total = 0;
      for (const Breakdown::Group& g : b.groups) total += g.n;
      for (const Breakdown::Group& g : b.groups) {
        const double p_g = StudentTTwoSided(
            g.t, std::max(1, total - static_cast<int>(groups)));
        if (g.label == "missing" || !(p_g * m * groups < alpha) ||
            std::abs(g.mean_residual_um) < material_um) {
          continue;
        }
        add(g, p_g, std::min(1.0, p_g * m * groups));
        ++listed;
      }
    }
    const Breakdown::Group* g = Carrier(b);
    if (listed == 0 && g != nullptr) add(*g, b.p_value, p_adj);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Unexplained& a, const Unexplained& b) {
                     return a.p_value < b.p_value;
                   });
  return out;
}

double MaterialResidualUm(const std::vector<double>& sd,
                          const DiagnosisThresholds& thresholds) {
  if (sd.empty()) return 0;
  std::vector<double> s = sd;
  std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
  return thresholds.material_noise_share * s[s.size() / 2];
}

}  // namespace rollwear::diag
