// The proxy guard's look along time (docs/diagnosis.md, "The proxy guard",
// "Along time"): a calendar-time term (started_at, measured_at, in any
// scope) claims to describe the structure of the mismatch along time, so it
// must take away most of the serially correlated part of it.
//
// Statistic. u_i = (measured - predicted) / sd_i on the training readings,
// clipped at +-kHuberK (robust.h), averaged per campaign in time order
// (started_at): x_1..x_n. The lag-1 autocovariance
//   gamma_1 = (1/n) sum_t (x_t - xbar)(x_{t+1} - xbar)
// is the part of the time structure white noise does not contribute to
// (its expectation is zero for independent campaign means, whatever their
// variance), unlike the variance of the x_t. Significance before the term:
// r1 = gamma_1 / gamma_0 with z = (r1 + 1/n) sqrt(n) ~ N(0, 1) under
// independence (Bartlett 1946, J. R. Stat. Soc. Suppl. 8:27; Box, Jenkins &
// Reinsel 2008, "Time Series Analysis", 4th ed., sec. 2.1.6).
//
// Rule. When gamma_1 before the term is positive and significant (p <
// alpha, two-sided; options.alpha = 0.001) and either more than
// along_time_share (one half) of it is left after the term, or what is left
// is itself significant at alpha with r1 >= material_autocorrelation, the
// term is not named: it is a smooth part of a structure along time it does
// not describe (a random walk of the wear rate has structure at every time
// scale; a step or a trend, once fitted, leaves campaign means that are
// close to independent). The lag-1 structure is then listed as unexplained.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/fit/robust.h"

namespace rollwear::diag {
namespace {

struct Lag1 {
  double gamma0 = 0, gamma1 = 0, r1 = 0, z = 0, p = 1, rms_um = 0;
  int n = 0;
};

// gamma_0, gamma_1, r1 and Bartlett's z of the campaign means of the
// clipped standardised residuals measured - pred (pred aligned with train).
Lag1 Lag1OfResiduals(const Dataset& data, const DiagnosisState& st,
                     const std::vector<double>& sd,
                     const std::vector<double>& pred) {
  const size_t m = st.train.size();
  std::vector<double> u(m), um(m);
  for (size_t i = 0; i < m; ++i) {
    const int o = st.train[i];
    um[i] = st.td.obs[o].measured_um - pred[i];
    u[i] = std::clamp(um[i] / sd[o], -kHuberK, kHuberK);
  }
  const CampaignSeries s = ByCampaignInTime(st.td, data, st.train, u, um);
  Lag1 l;
  l.n = static_cast<int>(s.u.size());
  if (l.n < 3) return l;
  double mean = 0;
  for (double v : s.u) mean += v;
  mean /= l.n;
  for (int t = 0; t < l.n; ++t) l.gamma0 += (s.u[t] - mean) * (s.u[t] - mean);
  for (int t = 0; t + 1 < l.n; ++t)
    l.gamma1 += (s.u[t] - mean) * (s.u[t + 1] - mean);
  for (double v : s.um) l.rms_um += v * v;
  l.gamma0 /= l.n;
  l.gamma1 /= l.n;
  l.rms_um = std::sqrt(l.rms_um / l.n);
  if (!(l.gamma0 > 0)) return l;
  l.r1 = l.gamma1 / l.gamma0;
  l.z = (l.r1 + 1.0 / l.n) * std::sqrt(static_cast<double>(l.n));
  l.p = ChiSquareSurvival(l.z * l.z, 1);  // two-sided normal
  return l;
}

}  // namespace

bool IsCalendarTerm(const TermData& td, const ModelTerm& t) {
  const int k = td.CovariateIndex(t.covariate);
  if (k < 0) return false;
  const CovariateSource s = td.catalog[k].source;
  return s == CovariateSource::kStartedAt || s == CovariateSource::kMeasuredAt;
}

GuardResult LookAlongTime(const Dataset& data, const DiagnosisState& st,
                          const DiagnosisOptions& options,
                          const std::vector<double>& sd,
                          const std::vector<double>& before,
                          const std::vector<double>& after,
                          const std::string& covariate) {
  GuardResult r;
  const Lag1 b = Lag1OfResiduals(data, st, sd, before);
  if (!(b.p < options.alpha) || !(b.gamma1 > 0)) return r;
  const Lag1 a = Lag1OfResiduals(data, st, sd, after);
  // Refused when more than along_time_share of the autocovariance remains,
  // or when what remains is itself significant and material (r1 at least
  // material_autocorrelation): a random walk of the wear rate, whose slow
  // part a binned or step term takes, leaves autocorrelated campaign means
  // behind; a step or a drift, once fitted, leaves near-independent ones.
  const bool still = a.p < options.alpha &&
                     a.r1 >= options.thresholds.material_autocorrelation;
  if (a.gamma1 <= options.thresholds.along_time_share * b.gamma1 && !still)
    return r;
  r.pass = false;
  char buf[200];
  std::snprintf(
      buf, sizeof(buf),
      "structure along time remains (lag-1 autocovariance of campaign means "
      "%.3f -> %.3f, r1 %+.2f -> %+.2f)",
      b.gamma1, a.gamma1, b.r1, a.r1);
  r.reason = buf;
  // Listed (when no candidate of the round passes) with the statistics of
  // the model that is kept, the one before the term: significant at alpha.
  r.located.dimension = "lag1_along_time";
  std::snprintf(buf, sizeof(buf),
                "campaign order (lag-1 autocorrelation %+.2f; a %s term took "
                "%.0f %% of its autocovariance)",
                b.r1, covariate.c_str(), 100.0 * (1.0 - a.gamma1 / b.gamma1));
  r.located.where = buf;
  r.located.test = "lag1_autocorrelation";
  r.located.statistic = b.z;
  r.located.mean_residual_um = b.rms_um;
  r.located.p_value = b.p;
  r.located.p_adjusted = b.p;
  return r;
}

}  // namespace rollwear::diag
