// Where the mismatch lives: residual breakdowns of the baseline model (step
// 2 of diagnosis.h). Categorical dimensions use a one-way ANOVA F test of the
// residuals (µm); numeric covariates a Pearson correlation t test of the
// relative residual (measured - predicted) / predicted against the
// covariate aggregated as the model aggregates it. With the robust noise
// sd's, each residual is first clipped to +-kHuberK sd (Huber's psi,
// robust.h), so a few gross grinder errors cannot locate a mismatch.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/base/distributions.h"
#include "core/fit/robust.h"

namespace rollwear::diag {

Breakdown AnovaBreakdown(const std::string& dimension, const std::vector<std::string>& label,
                         const std::vector<double>& resid, const std::vector<double>& rel,
                         const std::vector<std::string>& order) {
  Breakdown b;
  b.dimension = dimension;
  b.test = "anova";
  std::map<std::string, std::vector<int>> groups;
  for (size_t i = 0; i < label.size(); ++i) groups[label[i]].push_back(static_cast<int>(i));
  std::vector<std::string> keys = order;
  if (keys.empty()) {
    for (const auto& [k, v] : groups) keys.push_back(k);
  }
  const double n = static_cast<double>(resid.size());
  double grand = 0;
  for (double r : resid) grand += r;
  grand /= n;
  double ssb = 0, ssw = 0;
  int k_used = 0;
  for (const std::string& key : keys) {
    auto it = groups.find(key);
    if (it == groups.end()) continue;
    Breakdown::Group g;
    g.label = key;
    g.n = static_cast<int>(it->second.size());
    for (int i : it->second) {
      g.mean_residual_um += resid[i];
      g.mean_relative += rel[i];
    }
    g.mean_residual_um /= g.n;
    g.mean_relative /= g.n;
    for (int i : it->second) ssw += (resid[i] - g.mean_residual_um) * (resid[i] - g.mean_residual_um);
    ssb += g.n * (g.mean_residual_um - grand) * (g.mean_residual_um - grand);
    b.effect_size = std::max(b.effect_size, std::abs(g.mean_relative));
    b.groups.push_back(g);
    ++k_used;
  }
  if (k_used >= 2 && n > k_used && ssw > 0) {
    b.statistic = (ssb / (k_used - 1)) / (ssw / (n - k_used));
    b.p_value = FSurvival(b.statistic, k_used - 1, n - k_used);
    const double s_w = std::sqrt(ssw / (n - k_used));
    for (Breakdown::Group& g : b.groups) g.t = g.mean_residual_um / (s_w / std::sqrt(g.n));
  }
  return b;
}

std::string DominantGrade(const TermData& td, const TermObservation& o) {
  std::vector<double> by_grade(td.grades.size(), 0.0);
  for (int p = o.pass_begin; p < o.pass_end; ++p) by_grade[td.grade[p]] += td.load[p];
  return by_grade.empty()
             ? "?"
             : td.grades[std::max_element(by_grade.begin(), by_grade.end()) - by_grade.begin()];
}

std::string QuartileLabel(int q, const std::array<double, 3>& edges) {
  char buf[96];
  if (q == 0) std::snprintf(buf, sizeof(buf), "Q1 (< %.4g)", edges[0]);
  else if (q == 3) std::snprintf(buf, sizeof(buf), "Q4 (>= %.4g)", edges[2]);
  else std::snprintf(buf, sizeof(buf), "Q%d (%.4g - %.4g)", q + 1, edges[q - 1], edges[q]);
  return buf;
}

namespace {

// Quartile labels of values x (NaN -> "missing").
std::vector<std::string> Quartiles(const std::vector<double>& x, std::vector<std::string>* order) {
  std::vector<double> s;
  for (double v : x) {
    if (!std::isnan(v)) s.push_back(v);
  }
  std::sort(s.begin(), s.end());
  std::vector<std::string> out(x.size(), "missing");
  if (s.size() < 8) return out;
  const std::array<double, 3> edges = {s[s.size() / 4], s[s.size() / 2],
                                       s[3 * s.size() / 4]};
  for (int q = 0; q < 4; ++q) order->push_back(QuartileLabel(q, edges));
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(x[i])) continue;
    out[i] = QuartileLabel(QuartileOf(x[i], edges), edges);
  }
  return out;
}

// Time of day (UTC) of each observation's load: the 6-hour block holding
// most of it (a pass is rolled at started_at + hours_since_mount / 24 days).
// A night shift that rolls otherwise (a crew, the cooling water's
// temperature) lives here, and no recorded quantity follows it.
constexpr std::array<const char*, 4> kDayBlocks = {"00-06 h UTC", "06-12 h UTC",
                                                   "12-18 h UTC", "18-24 h UTC"};
std::vector<std::string> TimeOfDay(const TermData& td, const std::vector<int>& obs) {
  std::vector<std::string> block(obs.size(), "?");
  const int k_day = td.CovariateIndex("started_at");
  const int k_hours = td.CovariateIndex("hours_since_mount");
  if (k_day < 0 || k_hours < 0) return block;
  for (size_t i = 0; i < obs.size(); ++i) {
    const TermObservation& o = td.obs[obs[i]];
    std::array<double, 4> load{};
    for (int p = o.pass_begin; p < o.pass_end; ++p) {
      const double day = td.z[k_day][p] + td.z[k_hours][p] / 24;
      if (!std::isfinite(day)) continue;
      const double hour = (day - std::floor(day)) * 24;
      load[std::clamp(static_cast<int>(hour / 6), 0, 3)] += td.load[p];
    }
    const auto most = std::max_element(load.begin(), load.end());
    if (*most > 0) block[i] = kDayBlocks[most - load.begin()];
  }
  return block;
}

// The physical roll of each observation (mounts.csv roll_id; rolls come
// back after grinding): a roll that wears otherwise whenever it is mounted
// (a bad heat treatment, a soft batch) while its recorded hardness and
// diameter do not say so lives here. Rolls with fewer than
// thresholds.min_roll_readings readings share one group.
std::vector<std::string> RollIds(const Dataset& data, const TermData& td,
                                 const std::vector<int>& obs,
                                 const DiagnosisThresholds& thresholds) {
  std::vector<std::string> id(obs.size());
  std::map<std::string, int> count;
  for (size_t i = 0; i < obs.size(); ++i) {
    const int m = td.obs[obs[i]].mount;
    id[i] = m >= 0 && m < static_cast<int>(data.mounts.size()) ? data.mounts[m].roll_id : "";
    ++count[id[i]];
  }
  for (std::string& r : id) {
    if (r.empty() || count[r] < thresholds.min_roll_readings)
      r = "rolls with fewer readings";
  }
  return id;
}

}  // namespace

std::vector<Breakdown> Locate(const TermData& td, const Dataset& data,
                              const std::vector<int>& obs, const std::vector<double>& pred,
                              const DiagnosisThresholds& thresholds, const std::vector<double>* clip_sd) {
  const size_t n = obs.size();
  std::vector<double> resid(n), rel(n);
  for (size_t i = 0; i < n; ++i) {
    resid[i] = td.obs[obs[i]].measured_um - pred[i];
    if (clip_sd != nullptr) {  // Huber's psi: gross errors count as k sd's
      const double c = kHuberK * (*clip_sd)[i];
      resid[i] = std::clamp(resid[i], -c, c);
    }
    rel[i] = pred[i] > 0 ? resid[i] / pred[i] : 0.0;
  }
  std::vector<Breakdown> out;
  // Categorical dimensions.
  std::vector<std::string> position(n), roll_type(n), grade(n), amplitude(n);
  std::vector<double> length(n), time(n);
  const int k_len = td.CovariateIndex("length_m");
  const int k_time = td.CovariateIndex("started_at");
  for (size_t i = 0; i < n; ++i) {
    const TermObservation& o = td.obs[obs[i]];
    position[i] = td.positions[o.position];
    roll_type[i] = o.roll_type >= 0 ? td.roll_types[o.roll_type] : "?";
    double total_len = 0;
    for (int p = o.pass_begin; p < o.pass_end; ++p) {
      if (k_len >= 0) total_len += td.z[k_len][p];
    }
    grade[i] = DominantGrade(td, o);
    amplitude[i] = pred[i] < 150 ? "< 150 µm" : (pred[i] < 300 ? "150 - 300 µm" : ">= 300 µm");
    length[i] = total_len;
    time[i] = k_time >= 0 ? td.obs_z[k_time][obs[i]] : 0.0;
  }
  out.push_back(AnovaBreakdown("roll_position", position, resid, rel));
  out.push_back(AnovaBreakdown("roll_type", roll_type, resid, rel));
  out.push_back(AnovaBreakdown("dominant_grade", grade, resid, rel));
  out.push_back(AnovaBreakdown("wear_amplitude", amplitude, resid, rel,
                      {"< 150 µm", "150 - 300 µm", ">= 300 µm"}));
  std::vector<std::string> order;
  std::vector<std::string> q = Quartiles(length, &order);
  out.push_back(AnovaBreakdown("campaign_rolled_length_m", q, resid, rel, order));
  order.clear();
  q = Quartiles(time, &order);
  out.push_back(AnovaBreakdown("time_started_at_days", q, resid, rel, order));
  out.push_back(AnovaBreakdown("time_of_day", TimeOfDay(td, obs), resid, rel,
                               {kDayBlocks.begin(), kDayBlocks.end()}));
  out.push_back(AnovaBreakdown("roll_id", RollIds(data, td, obs, thresholds), resid, rel));
  // Numeric covariates: correlation with the relative residual.
  for (size_t k = 0; k < td.catalog.size(); ++k) {
    if (td.catalog[k].kind == CovariateKind::kFactor) continue;
    std::vector<double> x(n);
    double sx = 0, sy = 0;
    int m = 0;
    for (size_t i = 0; i < n; ++i) {
      x[i] = td.obs_z[k][obs[i]];
      if (std::isnan(x[i])) continue;
      sx += x[i];
      sy += rel[i];
      ++m;
    }
    if (m < 8) continue;
    const double mx = sx / m, my = sy / m;
    double sxx = 0, syy = 0, sxy = 0;
    for (size_t i = 0; i < n; ++i) {
      if (std::isnan(x[i])) continue;
      sxx += (x[i] - mx) * (x[i] - mx);
      syy += (rel[i] - my) * (rel[i] - my);
      sxy += (x[i] - mx) * (rel[i] - my);
    }
    if (!(sxx > 0 && syy > 0)) continue;
    std::vector<std::string> qorder;
    Breakdown b = AnovaBreakdown(td.catalog[k].name, Quartiles(x, &qorder), resid, rel, qorder);
    const double r = sxy / std::sqrt(sxx * syy);
    b.test = "pearson";
    b.statistic = r * std::sqrt((m - 2) / std::max(1e-300, 1 - r * r));
    b.p_value = StudentTTwoSided(b.statistic, m - 2);
    b.effect_size = std::abs(r);
    out.push_back(b);
  }
  std::stable_sort(out.begin(), out.end(), [](const Breakdown& a, const Breakdown& b) {
    return a.p_value < b.p_value;
  });
  return out;
}

}  // namespace rollwear::diag
