// A noise check of the final model's residuals (docs/diagnosis.md, "Noise
// checks", "Grade by campaign order"): does a grade wear differently
// depending on where in the campaign it is rolled? A fresh roll surface
// meeting a hard grade, or a grade scheduled right after the roll change,
// makes the wear of the same grade depend on its place in the campaign, a
// grade x campaign-order interaction no term of the vocabulary describes
// (K by grade takes the grade's average; campaign-order terms act on every
// grade alike).
//
// For a grade g and an opening window (the first w coils of the campaign,
// w the 10th and the 25th percentile of the coils-before count over the
// passes), each reading has s_g, the share of its base load rolled in g,
// and e_g, the share rolled in g inside the window. The partial regression
// of the standardised residual u on e_g given (1, s_g) asks whether the
// grade's opening coils wear otherwise than the rest of its coils: the t
// test of the partial correlation r, t = r sqrt((m - 3) / (1 - r^2)) ~
// t(m - 3) (Fisher 1924, Metron 3:329), with the campaign as the unit (u,
// s_g and e_g averaged over its readings: its rolls share its coils), m
// campaigns, Bonferroni over the grades and windows tried. The check's
// groups, for the size and the place, are the best (grade, window)'s:
// readings with some of the grade in the window, and with the grade only
// after it.
//
// The guard looks again with the same check (LookAtGradeOrder): a winner
// that takes part of such a structure (at least order_touched_share of its
// t^2) must take it below significance, or it is a stand-in: an unscoped
// campaign-order term (campaign_coils_before) fits part of a hard grade's
// opening coils without describing them
// (DiagnosisOrderTest.ACampaignOrderTermEverywhereIsNotNamedForIt).
//
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// y minus its least-squares fit on (1, x).
std::vector<double> Residualise(const std::vector<double>& y,
                                const std::vector<double>& x) {
  const double n = static_cast<double>(y.size());
  double mx = 0, my = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  const double b = sxx > 0 ? sxy / sxx : 0;
  std::vector<double> r(y.size());
  for (size_t i = 0; i < y.size(); ++i) r[i] = y[i] - my - b * (x[i] - mx);
  return r;
}

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double saa = 0, sbb = 0, sab = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    saa += a[i] * a[i];
    sbb += b[i] * b[i];
    sab += a[i] * b[i];
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0;
}

// One (grade, window) tried by the check: per reading, the regressor of
// interest x (the grade's share inside the window) and the control c (its
// share overall).
struct Trial {
  int grade = 0;
  double window = 0;
  std::vector<double> x, c;
};

// Means of v over the readings of each unit (unit[i] in 0..units-1).
std::vector<double> UnitMeans(const std::vector<double>& v,
                              const std::vector<int>& unit, int units) {
  std::vector<double> sum(units, 0.0), count(units, 0.0);
  for (size_t i = 0; i < v.size(); ++i) {
    sum[unit[i]] += v[i];
    count[unit[i]] += 1;
  }
  for (int k = 0; k < units; ++k) sum[k] = count[k] > 0 ? sum[k] / count[k] : 0;
  return sum;
}

// Appends the check for the trial with the smallest p of the partial
// correlation of u with x given (1, c), all three averaged over the
// readings of a campaign first (`unit`: the campaign of each reading,
// numbered 0..units-1): the rolls of one campaign share its coils, so
// their readings are one piece of evidence, not four. t = r sqrt((m - 3) /
// (1 - r^2)) ~ t(m - 3) over the m campaigns, Bonferroni over the trials;
// nothing when there is no trial. The groups (for the size and the
// place) are the readings with the grade: in the window, or only after it.
void AppendBestTrial(const TermData& td, const std::vector<Trial>& trials,
                     const std::vector<int>& unit, int units,
                     const std::vector<double>& u,
                     const std::vector<double>& um,
                     std::vector<Breakdown>* out) {
  if (trials.empty() || units < 8) return;
  const std::vector<double> uc = UnitMeans(u, unit, units);
  double best_p = 2, best_t = 0;
  const Trial* best = nullptr;
  for (const Trial& trial : trials) {
    const std::vector<double> c = UnitMeans(trial.c, unit, units);
    const double r = Correlation(
        Residualise(uc, c), Residualise(UnitMeans(trial.x, unit, units), c));
    const double m = static_cast<double>(units);
    const double t = r * std::sqrt((m - 3) / std::max(1e-300, 1 - r * r));
    const double p = StudentTTwoSided(t, m - 3);
    if (p < best_p) {
      best_p = p;
      best_t = t;
      best = &trial;
    }
  }
  if (best == nullptr) return;
  char in[96], later[96];
  const char* grade = td.grades[best->grade].c_str();
  std::snprintf(in, sizeof(in), "%s in the first %.0f coils", grade,
                best->window);
  std::snprintf(later, sizeof(later), "%s only after coil %.0f", grade,
                best->window);
  std::vector<std::string> label;
  std::vector<double> size;
  for (size_t i = 0; i < um.size(); ++i) {
    if (best->c[i] > 0) {
      label.push_back(best->x[i] > 0 ? in : later);
      size.push_back(um[i]);
    }
  }
  const std::vector<double> zero(size.size(), 0.0);
  Breakdown b = AnovaBreakdown("grade_by_campaign_order", label, size, zero);
  b.test = "partial_correlation";
  b.p_value = std::min(1.0, best_p * static_cast<double>(trials.size()));
  b.statistic = best_t;
  b.effect_size = 0;
  for (const Breakdown::Group& grp : b.groups) {
    b.effect_size = std::max(b.effect_size, std::abs(grp.mean_residual_um));
  }
  out->push_back(b);
}

// Per reading of `obs`, the share of its base load in grade g, and (with
// `in`) the share of it in grade g on passes where in(pass) holds.
template <typename In>
void GradeShares(const TermData& td, const std::vector<int>& obs, int g, In in,
                 std::vector<double>* share, std::vector<double>* share_in) {
  share->assign(obs.size(), 0.0);
  share_in->assign(obs.size(), 0.0);
  for (size_t i = 0; i < obs.size(); ++i) {
    const TermObservation& o = td.obs[obs[i]];
    double total = 0;
    for (int p = o.pass_begin; p < o.pass_end; ++p) {
      total += td.load[p];
      if (td.grade[p] != g) continue;
      (*share)[i] += td.load[p];
      if (in(p)) (*share_in)[i] += td.load[p];
    }
    if (total > 0) {
      (*share)[i] /= total;
      (*share_in)[i] /= total;
    }
  }
}

}  // namespace

void GradeByCampaignOrder(const TermData& td, const std::vector<int>& obs,
                          const std::vector<double>& u,
                          const std::vector<double>& um,
                          const DiagnosisThresholds& thresholds,
                          std::vector<Breakdown>* out) {
  const int k = td.CovariateIndex("campaign_coils_before");
  if (k < 0 || td.grades.size() < 2) return;
  std::vector<double> coils;
  for (int o : obs) {
    for (int p = td.obs[o].pass_begin; p < td.obs[o].pass_end; ++p) {
      if (std::isfinite(td.z[k][p])) coils.push_back(td.z[k][p]);
    }
  }
  if (coils.empty()) return;
  std::sort(coils.begin(), coils.end());
  std::vector<double> windows;
  for (double q : {0.10, 0.25}) {
    const double w =
        coils[static_cast<size_t>(q * static_cast<double>(coils.size() - 1))];
    if (w >= 1 && (windows.empty() || w > windows.back())) windows.push_back(w);
  }
  std::vector<Trial> trials;
  for (size_t g = 0; g < td.grades.size(); ++g) {
    for (double w : windows) {
      Trial t;
      t.grade = static_cast<int>(g);
      t.window = w;
      // NaN coils-before (not recorded) counts as outside the window.
      GradeShares(
          td, obs, t.grade, [&](int p) { return td.z[k][p] < w; }, &t.c, &t.x);
      const auto opening =
          std::count_if(t.x.begin(), t.x.end(), [](double e) { return e > 0; });
      if (opening < thresholds.min_opening_readings) continue;
      trials.push_back(std::move(t));
    }
  }
  std::vector<int> unit(obs.size());
  std::map<int, int> number;  // campaign -> 0..units-1
  for (size_t i = 0; i < obs.size(); ++i) {
    unit[i] =
        number.emplace(td.obs[obs[i]].campaign, static_cast<int>(number.size()))
            .first->second;
  }
  AppendBestTrial(td, trials, unit, static_cast<int>(number.size()), u, um,
                  out);
}

namespace {

// The check on the training readings with predictions `pred` (aligned with
// st.train), residuals clipped to +-kHuberK sd's.
Breakdown OrderCheck(const DiagnosisState& st, const std::vector<double>& sd,
                     const std::vector<double>& pred) {
  const size_t m = st.train.size();
  std::vector<double> u(m), um(m);
  for (size_t i = 0; i < m; ++i) {
    const int o = st.train[i];
    u[i] = std::clamp((st.td.obs[o].measured_um - pred[i]) / sd[o], -kHuberK,
                      kHuberK);
    um[i] = u[i] * sd[o];
  }
  std::vector<Breakdown> out;
  GradeByCampaignOrder(st.td, st.train, u, um, st.thresholds, &out);
  return out.empty() ? Breakdown{} : out.front();
}

}  // namespace

GuardResult LookAtGradeOrder(const DiagnosisState& st,
                             const DiagnosisOptions& options,
                             const std::vector<double>& sd,
                             const std::vector<double>& before,
                             const std::vector<double>& after) {
  GuardResult r;
  const Breakdown b = OrderCheck(st, sd, before);
  if (!(b.p_value < options.alpha)) return r;
  const Breakdown a = OrderCheck(st, sd, after);
  if (!(a.p_value < options.alpha)) return r;
  // A term that leaves the structure as it was is not about it (a real
  // temperature effect beside an order x grade one); one that takes part
  // of it and leaves the rest significant is a stand-in.
  if (a.statistic * a.statistic >
      (1 - options.thresholds.order_touched_share) * b.statistic * b.statistic)
    return r;
  const Breakdown::Group* g = Carrier(a);
  char buf[200];
  std::snprintf(buf, sizeof(buf),
                "grade x campaign-order structure remains (p adjusted %.2g -> "
                "%.2g)",
                b.p_value, a.p_value);
  r.pass = false;
  r.reason = buf;
  r.located.dimension = a.dimension;
  r.located.where = g != nullptr ? a.dimension + "=" + g->label : a.dimension;
  r.located.test = a.test;
  r.located.statistic = a.statistic;
  r.located.mean_residual_um = g != nullptr ? g->mean_residual_um : 0;
  r.located.p_value = a.p_value;
  r.located.p_adjusted = a.p_value;
  return r;
}

}  // namespace rollwear::diag
