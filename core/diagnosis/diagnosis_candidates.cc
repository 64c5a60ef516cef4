// The candidate-term library of the diagnosis engine (the naming of what
// it finds is in diagnosis_naming.cc); see diagnosis.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <string>
#include <utility>

#include "core/base/parallel.h"
#include "core/diagnosis/diagnosis_internal.h"

namespace rollwear::diag {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TermSpec Spec(int k, const CovariateSpec& c, TermForm form, std::vector<double> start,
              std::vector<double> lo, std::vector<double> hi) {
  TermSpec s;
  s.covariate = k;
  s.term.covariate = c.name;
  s.term.form = form;
  s.term.params = std::move(start);
  s.lower = std::move(lo);
  s.upper = std::move(hi);
  return s;
}

// A measurement-side text column: an additive offset per level, level
// `reference` read as is. Which level reads true is identified by the wear
// law itself (wear is proportional to the load, with no intercept, so a
// constant offset on every reading cannot be absorbed by K): one candidate
// per reference level with readings, and the tests choose, so that the odd
// gauge out is the one named (not the majority, relative to a minority).
TermSpec OffsetPerLevel(int k, const CovariateSpec& c, int levels, int reference) {
  TermSpec s = Spec(k, c, TermForm::kOffsetPerLevel, std::vector<double>(levels - 1, 0.0),
                    std::vector<double>(levels - 1, -1000.0),
                    std::vector<double>(levels - 1, 1000.0));
  s.term.num_levels = levels;
  s.term.reference_level = reference;
  s.term.levels.assign(c.levels.begin(),
                       c.levels.begin() + std::min<size_t>(levels, c.levels.size()));
  return s;
}

// The distinct inner quantile edges of `bins` equal-count bins.
std::vector<double> QuantileEdges(const WeightedValues& w, int bins) {
  std::vector<double> edges;
  for (int b = 1; b < bins; ++b) {
    const double e = Quantile(w, static_cast<double>(b) / bins);
    if (edges.empty() || e > edges.back()) edges.push_back(e);
  }
  return edges;
}

// A change on one day of the calendar (a new roll supplier, a recalibrated
// gauge): the binned form with a single edge t, so m = exp(b) (or the
// reading + o) from t on. The change point t is scanned over the
// step_grid inner quantiles of the covariate, one candidate each (the
// round's Bonferroni count includes every grid point, which pays for the
// scan; Andrews 1993, Econometrica 61:821, gives the exact sup-LR
// reference this bound stands in for). Quantile bins put their edges where
// the data fall, not where the change is: a step inside a bin leaves a
// part of it unexplained. Calendar covariates (started_at, measured_at)
// and a roll's earlier campaigns (roll_campaigns_before, locate-only) only:
// a step in another covariate is a threshold, which the binned form
// describes.
void AddSteps(int k, const CovariateSpec& c, const WeightedValues& w,
              const DiagnosisOptions& options, std::vector<Candidate>* out) {
  // Calendar steps (a new supplier, a recalibrated gauge), and a roll's
  // service from its n-th campaign on (a hard shell ground through): a
  // step on the roll's count is the rival a calendar step must beat, since
  // rolls serve in turn and a roll's service steps with the calendar while
  // the count's quartile bins can miss the edge
  // (DiagnosisProxyTest.ARollsServiceIsLocatedNotNamedAsCalendarTime).
  if (c.source != CovariateSource::kStartedAt &&
      c.source != CovariateSource::kMeasuredAt &&
      c.source != CovariateSource::kRollCampaignsBefore) {
    return;
  }
  const bool reading = c.level == CovariateLevel::kMeasurement;
  double last = -std::numeric_limits<double>::infinity();
  for (int g = 1; g < options.thresholds.step_grid; ++g) {
    const double t =
        Quantile(w, static_cast<double>(g) / options.thresholds.step_grid);
    if (!(t > last) || !(t < w.v.back().first)) continue;
    last = t;
    TermSpec step =
        reading
            ? Spec(k, c, TermForm::kOffsetBinned, {0.0}, {-1000.0}, {1000.0})
            : Spec(k, c, TermForm::kBinned, {0.0}, {-3.0}, {3.0});
    step.term.edges = {t};
    out->push_back({step, {}});
  }
}

}  // namespace

// See diagnosis_internal.h.
void MeanSd(const WeightedValues& w, double* mean, double* sd) {
  double s = 0, s2 = 0;
  for (const auto& [z, wt] : w.v) s += wt * z;
  *mean = s / w.total;
  for (const auto& [z, wt] : w.v) s2 += wt * (z - *mean) * (z - *mean);
  *sd = std::sqrt(s2 / w.total);
}

WeightedValues Collect(const TermData& td, const std::vector<int>& obs, int k) {
  WeightedValues w;
  const bool pass_level = td.catalog[k].level == CovariateLevel::kPass;
  for (int o : obs) {
    const TermObservation& ob = td.obs[o];
    if (pass_level) {
      for (int i = ob.pass_begin; i < ob.pass_end; ++i) {
        const double z = td.z[k][i];
        if (!std::isnan(z)) w.v.emplace_back(z, td.load[i]);
      }
    } else {
      const double z = td.obs_z[k][o];
      if (!std::isnan(z)) w.v.emplace_back(z, 1.0);
    }
  }
  std::sort(w.v.begin(), w.v.end());
  for (const auto& [z, wt] : w.v) w.total += wt;
  return w;
}

double Quantile(const WeightedValues& w, double q) {
  if (w.v.empty() || !(w.total > 0)) return kNaN;
  const double target = q * w.total;
  double acc = 0;
  for (const auto& [z, wt] : w.v) {
    acc += wt;
    if (acc >= target) return z;
  }
  return w.v.back().first;
}


double CovariateQuantile(const TermData& td, const std::vector<int>& obs, int k, double q) {
  return Quantile(Collect(td, obs, k), q);
}

namespace {

// The unscoped candidates over covariate k (none when it is a cell, which
// AddScopedCandidates offers, or the physical roll, which only the per-roll
// family fits; nor when k is too sparse, constant or a factor with too many
// levels).
std::vector<Candidate> CandidatesOf(const TermData& td, const std::vector<int>& train,
                                    int k, const DiagnosisOptions& options) {
  std::vector<Candidate> out;
  const CovariateSpec& c = td.catalog[k];
  if (c.source == CovariateSource::kCell || c.source == CovariateSource::kRollId) return out;
  const WeightedValues w = Collect(td, train, k);
  if (w.v.size() < 10) return out;
  const double p01 = Quantile(w, 0.01), p05 = Quantile(w, 0.05);
  const double p50 = Quantile(w, 0.5), p95 = Quantile(w, 0.95);
  if (c.kind == CovariateKind::kFactor) {
    int levels = 0;
    for (const auto& [z, wt] : w.v) levels = std::max(levels, static_cast<int>(z) + 1);
    if (levels < 2 || levels > options.max_factor_levels) return out;
    if (c.level == CovariateLevel::kMeasurement) {
      std::vector<double> count(levels, 0.0);
      for (const auto& [z, wt] : w.v) count[static_cast<int>(z)] += wt;
      for (int ref = 0; ref < levels; ++ref) {
        if (count[ref] > 0) out.push_back({OffsetPerLevel(k, c, levels, ref), {}});
      }
      return out;
    }
    TermSpec s = Spec(k, c, TermForm::kPerLevel, std::vector<double>(levels - 1, 0.0),
                      std::vector<double>(levels - 1, -3.0),
                      std::vector<double>(levels - 1, 3.0));
    s.term.num_levels = levels;
    s.term.levels.assign(c.levels.begin(),
                         c.levels.begin() + std::min<size_t>(levels, c.levels.size()));
    out.push_back({s, {}});
    return out;
  }
  if (c.kind == CovariateKind::kFlag) {
    double on = 0;
    for (const auto& [z, wt] : w.v) on += z > 0.5 ? wt : 0.0;
    if (on < 0.02 * w.total || on > 0.98 * w.total) return out;
    out.push_back({Spec(k, c, TermForm::kFlag, {0.0}, {-3.0}, {3.0}), {}});
    return out;
  }
  if (!(p95 > p05)) return out;  // (nearly) constant
  double mean, sd;
  MeanSd(w, &mean, &sd);
  if (!(sd > 0)) return out;
  if (c.level == CovariateLevel::kMeasurement) {
    TermSpec lin = Spec(k, c, TermForm::kOffsetLinear, {0.0}, {-1000.0}, {1000.0});
    lin.term.center = mean;
    lin.term.scale = sd;
    out.push_back({lin, {}});
    // A reading that steps or drifts unevenly: one offset per quantile bin.
    const std::vector<double> edges = QuantileEdges(w, options.num_bins);
    if (edges.size() >= 2 && edges.back() < w.v.back().first) {
      const int nb = static_cast<int>(edges.size());
      TermSpec bin = Spec(k, c, TermForm::kOffsetBinned, std::vector<double>(nb, 0.0),
                          std::vector<double>(nb, -1000.0), std::vector<double>(nb, 1000.0));
      bin.term.edges = edges;
      out.push_back({bin, {}});
    }
    if (p01 >= 0 && p50 > 0) {
      Candidate dec{Spec(k, c, TermForm::kOffsetDecay, {0.0, std::log(p50)},
                         {-1000.0, std::log(0.02 * p50)}, {1000.0, std::log(20 * p95)}),
                    {}};
      for (double f : {0.25, 1.0, 4.0}) dec.starts.push_back({0.0, std::log(f * p50)});
      out.push_back(dec);
    }
    AddSteps(k, c, w, options, &out);
    return out;
  }
  TermSpec ll = Spec(k, c, TermForm::kLogLinear, {0.0}, {-2.0}, {2.0});
  ll.term.center = mean;
  ll.term.scale = sd;
  out.push_back({ll, {}});
  if (p01 > 0) {
    TermSpec pw = Spec(k, c, TermForm::kPower, {0.0}, {-4.0}, {4.0});
    pw.term.center = mean;
    out.push_back({pw, {}});
  }
  const std::vector<double> edges = QuantileEdges(w, options.num_bins);
  if (edges.size() >= 2 && edges.back() < w.v.back().first) {
    const int nb = static_cast<int>(edges.size());
    TermSpec bin = Spec(k, c, TermForm::kBinned, std::vector<double>(nb, 0.0),
                        std::vector<double>(nb, -3.0), std::vector<double>(nb, 3.0));
    bin.term.edges = edges;
    out.push_back({bin, {}});
  }
  AddSteps(k, c, w, options, &out);
  if (c.accumulates && p95 > 0 && p05 >= 0) {
    Candidate sat{Spec(k, c, TermForm::kSaturating, {0.0, std::log(p95)},
                       {-0.9, std::log(0.05 * p95)}, {10.0, std::log(20 * p95)}),
                  {}};
    for (double f : {0.2, 1.0, 5.0}) sat.starts.push_back({0.0, std::log(f * p95)});
    out.push_back(sat);
    Candidate dec{Spec(k, c, TermForm::kDecaying, {0.0, std::log(0.1 * p95)},
                       {-0.9, std::log(0.005 * p95)}, {10.0, std::log(p95)}),
                  {}};
    for (double f : {0.02, 0.1, 0.4}) dec.starts.push_back({0.0, std::log(f * p95)});
    out.push_back(dec);
  }
  return out;
}

}  // namespace

std::vector<std::vector<Candidate>> UnscopedCandidates(const TermData& td,
                                                       const std::vector<int>& train,
                                                       const DiagnosisOptions& options) {
  // One slot per covariate, filled in parallel.
  const int nk = static_cast<int>(td.catalog.size());
  std::vector<std::vector<Candidate>> per(nk);
  ParallelFor(nk, options.num_threads,
              [&](int k) { per[k] = CandidatesOf(td, train, k, options); });
  return per;
}

std::vector<Candidate> MakeCandidates(
    const TermData& td, const std::vector<int>& train,
    const std::set<int>& used,
    const std::vector<std::vector<Candidate>>& unscoped,
    const DiagnosisThresholds& thresholds,
    const std::vector<TermScope>& adopted_cells) {
  // Joined in catalogue order.
  std::vector<Candidate> out;
  for (size_t k = 0; k < unscoped.size(); ++k) {
    if (used.count(static_cast<int>(k)) > 0) continue;
    out.insert(out.end(), unscoped[k].begin(), unscoped[k].end());
  }
  AddScopedCandidates(td, train, thresholds, used, adopted_cells, &out);
  return out;
}

std::vector<Candidate> MakeCandidates(const TermData& td, const std::vector<int>& train,
                                      const std::set<int>& used,
                                      const DiagnosisOptions& options,
                                      const std::vector<TermScope>& adopted_cells) {
  return MakeCandidates(td, train, used, UnscopedCandidates(td, train, options),
                        options.thresholds, adopted_cells);
}

}  // namespace rollwear::diag
