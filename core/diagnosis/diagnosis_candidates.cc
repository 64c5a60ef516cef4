// The candidate terms of the diagnosis engine: each covariate summarised
// and the term families asked for their proposals over it
// (core/model/term_family.h), the calendar steps added; the naming of what
// it finds is in diagnosis_naming.cc; see diagnosis.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "core/base/parallel.h"
#include "core/diagnosis/diagnosis_internal.h"
#include "core/model/term_family.h"

namespace rollwear::diag {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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
void AddSteps(const CovariateSummary& s, const WeightedValues& w,
              const DiagnosisOptions& options, std::vector<TermProposal>* out) {
  const CovariateSpec& c = *s.spec;
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
    const double bound = reading ? 1000.0 : 3.0;
    out->push_back(Proposal(
        FamilyOf(reading ? TermForm::kOffsetBinned : TermForm::kBinned), s,
        {0.0}, {-bound}, {bound}));
    out->back().term.edges = {t};
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

// The summary of covariate k the families propose from, or nullopt when
// k cannot carry a term: a factor with fewer than 2 or more than
// max_factor_levels levels, a flag on for under 2 % or over 98 % of the
// weight, a numeric covariate that is (nearly) constant.
std::optional<CovariateSummary> SummariseCovariate(
    const CovariateSpec& c, const WeightedValues& w,
    const DiagnosisOptions& options) {
  CovariateSummary s;
  s.spec = &c;
  s.p01 = Quantile(w, 0.01);
  s.p05 = Quantile(w, 0.05);
  s.p50 = Quantile(w, 0.5);
  s.p95 = Quantile(w, 0.95);
  s.max = w.v.back().first;
  if (c.kind == CovariateKind::kFactor) {
    for (const auto& [z, wt] : w.v)
      s.levels = std::max(s.levels, static_cast<int>(z) + 1);
    if (s.levels < 2 || s.levels > options.max_factor_levels)
      return std::nullopt;
    s.level_weight.assign(s.levels, 0.0);
    for (const auto& [z, wt] : w.v) s.level_weight[static_cast<int>(z)] += wt;
    return s;
  }
  if (c.kind == CovariateKind::kFlag) {
    double on = 0;
    for (const auto& [z, wt] : w.v) on += z > 0.5 ? wt : 0.0;
    const double share = options.thresholds.min_flag_share;
    if (on < share * w.total || on > (1 - share) * w.total) return std::nullopt;
    return s;
  }
  if (!(s.p95 > s.p05)) return std::nullopt;  // (nearly) constant
  MeanSd(w, &s.mean, &s.sd);
  if (!(s.sd > 0)) return std::nullopt;
  s.edges = QuantileEdges(w, options.num_bins);
  return s;
}

// The unscoped candidates over covariate k: each family's proposals, in
// the registry's order (core/model/term_family.cc), and the calendar steps
// after the binned family's. None when k is a cell, which
// AddScopedCandidates offers, or the physical roll, which only the
// per-roll family fits; nor when k is too sparse or cannot carry a term.
std::vector<Candidate> CandidatesOf(const TermData& td, const std::vector<int>& train,
                                    int k, const DiagnosisOptions& options) {
  std::vector<Candidate> out;
  const CovariateSpec& c = td.catalog[k];
  if (c.source == CovariateSource::kCell || c.source == CovariateSource::kRollId) return out;
  const WeightedValues w = Collect(td, train, k);
  if (w.v.size() < 10) return out;
  const std::optional<CovariateSummary> summary =
      SummariseCovariate(c, w, options);
  if (!summary) return out;
  std::vector<TermProposal> proposals;
  for (const TermFamily* family : AllTermFamilies()) {
    proposals.clear();
    family->Propose(*summary, &proposals);
    if (family->form() == TermForm::kBinned &&
        c.kind == CovariateKind::kNumeric) {
      AddSteps(*summary, w, options, &proposals);
    }
    for (TermProposal& p : proposals) {
      TermSpec spec;
      spec.covariate = k;
      spec.term = std::move(p.term);
      spec.lower = std::move(p.lower);
      spec.upper = std::move(p.upper);
      out.push_back({std::move(spec), std::move(p.starts)});
    }
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
