// The proxy guard's look again (docs/diagnosis.md, "The proxy guard"; the
// chain is in diagnosis_guard.cc): the breakdown that located the mismatch
// most strongly (Locate on the training residuals of the model before the
// term; only if it is itself significant at the family-wise level,
// Bonferroni over the breakdowns) must be materially reduced after the
// term: no longer significant, or its largest group mean residual at most
// thresholds.look_again_shrink of what it was. Otherwise the term fitted
// something else and the located structure is still there: not adopted.
//
// Beside the rolls. When that structure is along roll_id, it may be the
// rolls' own wear resistance (material, supplier, heat treatment: a
// scatter every mill's rolls have, which the per-roll family absorbs
// after the rounds, diagnosis_roll_family.cc) and not the candidate's
// place: a grinder reading 28 um high, p = 1e-151, was refused because the
// 3 % roll scatter beside it stayed. The candidate is then judged on the
// model that carries that scatter, as joint selection judges a candidate
// beside the other located structure: with a per-roll term R (its spread
// tau from the current model's scatter, DerSimonian & Laird 1986) in both
// models, (i) the candidate must still add: LR = n ln(RSS_{cur+R} /
// RSS_{cur+R+term}) / deff ~ chi2(df) (Wilks 1938, Ann. Math. Stat. 9:60),
// df its parameters, deff the campaign design effect below (which the
// round's own test does not apply), at options.alpha with the round's
// Bonferroni count; a stand-in for the rolls' scatter adds little there;
// and (ii) the strongest breakdown other than roll_id beside R must be
// materially reduced by it, the look again above.
// Thread-safety: reentrant (reads its arguments only).
#include "core/diagnosis/diagnosis_look_again.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/base/intraclass.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

double LargestGroupMean(const Breakdown& b) {
  double m = 0;
  for (const Breakdown::Group& g : b.groups) {
    if (g.label != "missing") m = std::max(m, std::abs(g.mean_residual_um));
  }
  return m;
}

}  // namespace

// The design effect of the nested test of a candidate whose fitted
// contribution is p_after - p_before on the training readings: readings of
// one campaign share its noise (the rolls' temperature, the strip
// schedule, the grinder's day), so they are not independent, and a
// candidate that is (nearly) constant over a campaign's readings, such as
// a campaign-level quantity, is tested on fewer independent units than it
// has readings. For a regression coefficient the variance grows by
//   deff = 1 + (n0 - 1) rho_e rho_x
// (Scott & Holt 1982, J. Amer. Statist. Assoc. 77:848), rho_e the
// intraclass correlation within campaigns of the standardised residuals
// under the fitted model (with the candidate, p_after: the errors', not
// the candidate's own, correlation), rho_x that of the candidate's
// standardised contribution, n0 the mean campaign size (intraclass.h). The
// LR statistic is divided by it (>= 1).
double CampaignDesignEffect(const DiagnosisState& st,
                            const std::vector<double>& sd,
                            const std::vector<double>& p_before,
                            const std::vector<double>& p_after) {
  std::vector<double> residual, contribution;
  std::vector<int> campaign;
  for (size_t i = 0; i < st.train.size(); ++i) {
    const int o = st.train[i];
    const TermObservation& ob = st.td.obs[o];
    residual.push_back((ob.measured_um - p_after[i]) / sd[o]);
    contribution.push_back((p_after[i] - p_before[i]) / sd[o]);
    campaign.push_back(ob.campaign);
  }
  const Intraclass e = OneWayIntraclass(residual, campaign);
  const Intraclass x = OneWayIntraclass(contribution, campaign);
  return std::max(1.0, 1 + (e.n0 - 1) * e.rho * x.rho);
}

GuardResult LookAgain(const Dataset& data, const DiagnosisState& st,
                      const DiagnosisOptions& options,
                      const std::vector<Breakdown>& before,
                      const std::vector<double>& clip,
                      const std::vector<double>& after) {
  GuardResult r;
  if (before.empty()) return r;
  const double m = static_cast<double>(before.size());
  const Breakdown& top = before.front();  // strongest first
  if (!(top.p_value * m < options.alpha)) return r;
  for (const Breakdown& b :
       Locate(st.td, data, st.train, after, options.thresholds, &clip)) {
    if (b.dimension != top.dimension) continue;
    const bool gone = !(b.p_value * m < options.alpha);
    const bool shrunk =
        LargestGroupMean(b) <=
        options.thresholds.look_again_shrink * LargestGroupMean(top);
    if (!gone && !shrunk) {
      r.pass = false;
      char buf[160];
      std::snprintf(
          buf, sizeof(buf),
          "located structure remains (%s: largest group mean %.1f -> %.1f um)",
          top.dimension.c_str(), LargestGroupMean(top), LargestGroupMean(b));
      r.reason = buf;
      // Where the structure the candidate failed to take away lives: its
      // largest group after the term (listed as unexplained when no
      // candidate of the round passes, so the verdict cannot be "noise").
      const Breakdown::Group* largest = Carrier(b);
      r.located.dimension = b.dimension;
      r.located.where =
          largest != nullptr ? b.dimension + "=" + largest->label : b.dimension;
      r.located.test = b.test;
      r.located.statistic = b.statistic;
      r.located.mean_residual_um =
          largest != nullptr ? largest->mean_residual_um : 0;
      r.located.p_value = b.p_value;
      r.located.p_adjusted = std::min(1.0, b.p_value * m);
    }
  }
  return r;
}

GuardResult LookAgainBesideRolls(const Dataset& data, const DiagnosisState& st,
                                 const DiagnosisOptions& options,
                                 const std::vector<double>& sd,
                                 const Fitted& with_term,
                                 const std::vector<double>& clip,
                                 double num_tests,
                                 const GuardResult& look_again) {
  if (look_again.pass || look_again.located.dimension != kRollIdName)
    return look_again;
  const auto holds_rolls = [](const std::vector<TermSpec>& terms) {
    return std::any_of(terms.begin(), terms.end(), [](const TermSpec& t) {
      return t.term.form == TermForm::kRollEffect;
    });
  };
  TermSpec rolls;
  if (holds_rolls(with_term.terms) ||
      !RollScatterTerm(st, options, sd, st.current, &rolls)) {
    return look_again;
  }
  const Fitted before = FitWith(st, sd, st.current, rolls);
  const Fitted after = FitWith(st, sd, with_term, rolls);
  if (!before.usable || !after.usable || !(before.rss > 0) ||
      !(after.rss > 0)) {
    return look_again;
  }
  // (i) The candidate adds beside the rolls' own scatter.
  const std::vector<double> p_before =
      PredictTerms(st.td, st.train, before.log_k, before.terms);
  const std::vector<double> p_after =
      PredictTerms(st.td, st.train, after.log_k, after.terms);
  const double df = with_term.terms.back().term.NumParams();
  if (!(df > 0)) return look_again;
  const double deff = CampaignDesignEffect(st, sd, p_before, p_after);
  const double lr =
      Encompassed(st, before, after, static_cast<int>(df)).lr / deff;
  const double p = ChiSquareSurvival(lr, df);
  // The candidate's own effect tested again, beside the rolls: one of the
  // round's tests.
  const Multiplicity round = RoundFamily(options, num_tests);
  const double p_adjusted = round.Adjusted(p);
  if (!round.Rejects(p)) {
    GuardResult r = look_again;
    char buf[200];
    std::snprintf(buf, sizeof(buf),
                  "a stand-in for the rolls' own scatter: beside per-roll "
                  "multipliers it adds too little (LR %.1f on %.0f df, "
                  "design effect %.1f, p adjusted %.2g)",
                  lr, df, deff, p_adjusted);
    r.reason = buf;
    return r;
  }
  // (ii) The strongest other structure beside the rolls is taken away.
  std::vector<Breakdown> located =
      Locate(st.td, data, st.train, p_before, options.thresholds, &clip);
  located.erase(std::remove_if(located.begin(), located.end(),
                               [](const Breakdown& b) {
                                 return b.dimension == kRollIdName;
                               }),
                located.end());
  return LookAgain(data, st, options, located, clip, p_after);
}

}  // namespace rollwear::diag
