// The proxy guard's comparison with the round's rivals (docs/diagnosis.md,
// "The proxy guard", "Rival covariates"): a winner names one covariate,
// and so claims that the other accepted candidates of the round are worse
// descriptions. Strip speed, coil length and entry thickness move together
// (mass flow through the stands), so a speed effect on one roll type is
// fitted almost as well by a length term on it (session-14 scorecard:
// named `length_m` with p = 3e-16 while the truth was speed). The winner is
// named only when it explains something each rival does not, by the
// encompassing test (Mizon & Richard 1986, Econometrica 54:657): the
// nested likelihood ratio of the winner's term added to the rival's model,
// LR = n ln(RSS_rival / RSS_rival+winner) ~ chi2(df_winner) (Wilks 1938,
// Ann. Math. Stat. 9:60), at alternative_alpha (diagnosis_alternatives.h)
// for each rival. Naming needs every rival's test to reject, an
// intersection-union test (Berger 1982, Technometrics 24:295): each at level
// alpha bounds the chance of naming a covariate the data do not prefer, with no
// multiplicity correction. Since RSS_rival+winner <= RSS_winner, n ln(RSS_rival
// / RSS_winner) is a lower bound of that LR: a rival it already clears needs no
// joint fit. A rival is an accepted candidate over another covariate that is
// not a factor cell (NoBetterThanCell compares those). When the winner adds
// nothing significant to a rival, the data do not say which of the two
// quantities drives the wear: the winner is not named, and where the
// mismatch lives (along the covariate, in the scope) is listed instead.
// A rival may be locate-only (roll_campaigns_before, covariates.h): a
// calendar drift must add to a roll's service to be named, since rolls
// serve in turn and a roll's service follows the calendar (correlation
// 0.83 in an independent generator's mills); so must an hours-in-service
// term add to extra wear on the first coils after a stop (after_stop),
// which the number of stops drives in both. NotNameable refuses such a
// candidate itself and lists where it lives.
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/model/covariates.h"
#include "core/model/term_family.h"

namespace rollwear::diag {
namespace {

// A locate-only rival (a quantity the data format does not name) that adds
// nothing to the winner either is the same description, and the recorded
// covariate is named: a mill's own column of each roll's regrinds is a
// roll's earlier campaigns (an independent generator's `regrinds`, named
// before the rival existed and refused as "not distinguishable" with it).
// The reverse encompassing test: the rival's term added to the winner's
// model, LR = n ln(RSS_winner / RSS_joint) ~ chi2(df_rival), at the same
// thresholds.alternative_alpha; its lower bound n ln(RSS_winner / RSS_rival)
// first.
bool EncompassesLocateOnly(const DiagnosisState& st,
                           const std::vector<Fitted>& fits, int winner,
                           int rival, const Fitted& joint) {
  const TermSpec& rival_term = fits[rival].terms.back();
  if (!st.td.catalog[rival_term.covariate].locate_only) return false;
  const double n = static_cast<double>(st.train.size());
  const int df = rival_term.term.NumParams();
  const Multiplicity each = EachOf(st.thresholds);
  double lr = NestedLr(n, fits[winner].rss, fits[rival].rss);
  if (each.Rejects(ChiSquareSurvival(lr, df))) return false;
  if (!joint.usable || !(joint.rss > 0))
    return false;  // cannot tell: not named
  lr = std::max(lr, NestedLr(n, fits[winner].rss, joint.rss));
  return !each.Rejects(ChiSquareSurvival(lr, df));
}

// The encompassing test of fitted candidate `adding` against fitted
// candidate `base`: the term of `adding` added to the model of `base`,
// LR = n ln(RSS_base / RSS_base+adding) ~ chi2(df_adding), its lower bound
// n ln(RSS_base / RSS_adding) first. `joint` is fitted only when the bound
// does not clear the level (EachOf: the winner must add to every rival); a
// failed joint fit leaves the bound.
struct Addition {
  double lr = 0;
  double p = 1;
  Fitted joint;
};
Addition AddsTo(const DiagnosisState& st, const std::vector<double>& sd,
                const std::vector<Fitted>& fits, int adding, int base) {
  Addition e;
  const TermSpec& term = fits[adding].terms.back();
  const double n = static_cast<double>(st.train.size());
  const int df = term.term.NumParams();
  e.lr = NestedLr(n, fits[base].rss, fits[adding].rss);
  e.p = ChiSquareSurvival(e.lr, df);
  if (EachOf(st.thresholds).Rejects(e.p)) return e;
  const Encompassing joint = Encompass(st, sd, fits[base], term);
  e.joint = joint.with;
  if (joint.usable() && joint.lr > e.lr) {
    e.lr = joint.lr;
    e.p = joint.p;
  }
  return e;
}

// Whether the data cannot tell `a` from `b` either way: neither term adds
// significantly (at alternative_alpha) to the other's model.
bool TiedBothWays(const DiagnosisState& st, const std::vector<double>& sd,
                  const std::vector<Fitted>& fits, int a, int b) {
  const Multiplicity each = EachOf(st.thresholds);
  return !each.Rejects(AddsTo(st, sd, fits, a, b).p) &&
         !each.Rejects(AddsTo(st, sd, fits, b, a).p);
}

}  // namespace

double ContributionRmsUm(const DiagnosisState& st, const Fitted& with,
                         const Fitted& without,
                         const std::vector<TermScope>& scopes) {
  const std::vector<double> a =
      PredictTerms(st.td, st.train, with.log_k, with.terms);
  const std::vector<double> b =
      PredictTerms(st.td, st.train, without.log_k, without.terms);
  double sum2 = 0;
  int count = 0;
  for (size_t i = 0; i < st.train.size(); ++i) {
    const TermObservation& ob = st.td.obs[st.train[i]];
    if (std::none_of(scopes.begin(), scopes.end(), [&](const TermScope& s) {
          return InScope(st.td, ob, s);
        })) {
      continue;
    }
    sum2 += (a[i] - b[i]) * (a[i] - b[i]);
    ++count;
  }
  return count > 0 ? std::sqrt(sum2 / count) : 0;
}

namespace {

// Where a refused candidate lives: at `where` along its covariate, the
// size of its term's contribution over its scope, its LR and p.
Unexplained LocatedByItsLr(const DiagnosisState& st,
                           const std::vector<Fitted>& fits,
                           const std::vector<CandidateResult>& results,
                           int candidate, const std::string& where) {
  const CandidateResult& c = results[candidate];
  Unexplained u;
  u.dimension = c.covariate;
  u.where = where;
  u.mean_residual_um =
      ContributionRmsUm(st, fits[candidate], st.current,
                        {fits[candidate].terms.back().term.scope});
  u.test = "lr";
  u.statistic = c.lr;
  u.p_value = c.p_value;
  u.p_adjusted = c.p_adjusted;
  return u;
}

}  // namespace

GuardResult NotNameable(const DiagnosisState& st,
                        const std::vector<Fitted>& fits,
                        const std::vector<CandidateResult>& results,
                        int candidate) {
  GuardResult r;
  const TermSpec& term = fits[candidate].terms.back();
  if (!st.td.catalog[term.covariate].locate_only) return r;
  const CandidateResult& c = results[candidate];
  r.pass = false;
  const CovariateSource source = st.td.catalog[term.covariate].source;
  const bool stops = source == CovariateSource::kAfterStop;
  r.reason =
      "follows " + c.covariate + ", a quantity derived from " +
      (stops ? "the gaps between the coils' rolled_at" : "the roll serials") +
      " that the data format does not name: located, not named";
  // One entry per covariate (AddLocated drops a same-place repeat): the
  // strongest form's, refused first.
  r.located = LocatedByItsLr(
      st, fits, results, candidate,
      source == CovariateSource::kRollCampaignsBefore
          ? "each roll's earlier campaigns (roll_id)"
          : (stops ? "the first coils after a stop (rolled_at)" : c.covariate));
  return r;
}

GuardResult AtBoxBound(const DiagnosisState& st,
                       const std::vector<Fitted>& fits,
                       const std::vector<CandidateResult>& results,
                       int candidate) {
  GuardResult r;
  const TermSpec& term = fits[candidate].terms.back();
  const TermFamily& family = FamilyOf(term.term.form);
  const std::vector<double>& x = term.term.params;
  for (size_t j = 0; j < x.size() && j < term.lower.size(); ++j) {
    const double lo = term.lower[j], hi = term.upper[j];
    const double tol = 1e-4 * (hi - lo);
    const bool at_lo = x[j] <= lo + tol, at_hi = x[j] >= hi - tol;
    if (!(at_lo || at_hi) || family.BoundIsALimit(static_cast<int>(j), at_hi))
      continue;
    r.pass = false;
    const int k = static_cast<int>(j);
    const TermParamView at = family.Param(k, x[j]);
    const TermParamView bound = family.Param(k, at_hi ? hi : lo);
    char buf[320];
    std::snprintf(buf, sizeof(buf),
                  "its fit stops at the edge of the box it is fitted in "
                  "(%s = %.4g, at its %s bound %.4g): the %s form stands in "
                  "for structure it does not describe; located, not named",
                  at.name.c_str(), at.value, at_hi ? "upper" : "lower",
                  bound.value, family.name());
    r.reason = buf;
    r.located = LocatedByItsLr(st, fits, results, candidate,
                               results[candidate].covariate);
    return r;
  }
  return r;
}

namespace {

// The refusal of a winner the data cannot tell from a rival: `reason`, and
// located at `where` with the size of the winner's term over its scope and
// the winner's own test.
GuardResult NotDistinguishable(const DiagnosisState& st,
                               const std::vector<Fitted>& fits,
                               const std::vector<CandidateResult>& results,
                               int winner, const std::string& reason,
                               const std::string& where) {
  GuardResult r;
  r.pass = false;
  r.reason = reason;
  r.located.dimension = results[winner].covariate;
  r.located.where = where;
  r.located.mean_residual_um = ContributionRmsUm(
      st, fits[winner], st.current, {fits[winner].terms.back().term.scope});
  r.located.test = "encompassing_lr";
  r.located.statistic = results[winner].lr;
  r.located.p_value = results[winner].p_value;
  r.located.p_adjusted = results[winner].p_adjusted;
  return r;
}

}  // namespace

GuardResult DistinctFromRivals(const DiagnosisState& st,
                               const std::vector<double>& sd,
                               const std::vector<int>& accepted,
                               const std::vector<Fitted>& fits,
                               const std::vector<CandidateResult>& results,
                               int winner) {
  GuardResult r;
  const TermSpec& term = fits[winner].terms.back();
  if (term.term.form == TermForm::kCell) return r;
  std::vector<int> rivals;
  for (int j : accepted) {
    if (j != winner && results[j].covariate != results[winner].covariate &&
        fits[j].terms.back().term.form != TermForm::kCell && fits[j].usable) {
      rivals.push_back(j);
    }
  }
  if (rivals.empty()) return r;
  // Named only when it adds to every rival (EachOf).
  const Multiplicity each = EachOf(st.thresholds);
  for (int j : rivals) {
    const Addition e = AddsTo(st, sd, fits, winner, j);
    if (each.Rejects(e.p)) continue;
    if (EncompassesLocateOnly(st, fits, winner, j, e.joint)) continue;
    const double lr = e.lr, p = e.p;
    const TermScope& scope = term.term.scope;
    // One mechanism, two carriers, one place, and the rival adds nothing
    // to the winner either: the mechanism is named (CarriersOf lists the
    // carriers). A rival that does add is the better description, and
    // the winner is refused as before.
    if (SameCarriedMechanism(results[winner].covariate, results[j].covariate) &&
        !FamilyOf(term.term.form).names_mechanism() &&
        !FamilyOf(fits[j].terms.back().term.form).names_mechanism() &&
        fits[j].terms.back().term.scope.Label() == scope.Label() &&
        !each.Rejects(AddsTo(st, sd, fits, j, winner).p)) {
      continue;
    }
    const std::string where =
        scope.Fields().empty() ? std::string("everywhere") : scope.Label();
    const TermScope& rival_scope = fits[j].terms.back().term.scope;
    const std::string rival =
        results[j].covariate +
        (rival_scope.Fields().empty() ? "" : " (" + rival_scope.Label() + ")");
    char buf[320];
    std::snprintf(buf, sizeof(buf),
                  "not distinguishable from %s: given it, the term adds LR "
                  "%.1f, p %.2g; the data do not say which quantity drives "
                  "the wear",
                  rival.c_str(), lr, p);
    return NotDistinguishable(st, fits, results, winner, buf,
                              where + ": along " + results[winner].covariate +
                                  " or " + results[j].covariate);
  }
  return r;
}

GuardResult DistinctFromOtherGates(const DiagnosisState& st,
                                   const std::vector<double>& sd,
                                   const std::vector<Fitted>& fits,
                                   const std::vector<CandidateResult>& results,
                                   int winner) {
  GuardResult r;
  const ModelTerm& term = fits[winner].terms.back().term;
  if (term.scope.gate.empty()) return r;
  for (int j = 0; j < static_cast<int>(fits.size()); ++j) {
    if (!fits[j].usable || !(fits[j].rss > 0)) continue;
    const ModelTerm& other = fits[j].terms.back().term;
    if (other.scope.gate.empty() || other.scope.gate == term.scope.gate ||
        other.covariate != term.covariate || other.form != term.form ||
        other.scope.Label() == term.scope.Label()) {
      continue;
    }
    const Addition e = AddsTo(st, sd, fits, winner, j);
    if (EachOf(st.thresholds).Rejects(e.p)) continue;
    char buf[320];
    std::snprintf(buf, sizeof(buf),
                  "not distinguishable from the same term on %s: given it, "
                  "the gate on %s adds LR %.1f, p %.2g; the data do not say "
                  "which quantity gates the effect",
                  other.scope.Label().c_str(), term.scope.gate.c_str(), e.lr,
                  e.p);
    return NotDistinguishable(st, fits, results, winner, buf,
                              results[winner].covariate +
                                  " behind a gate: along " + term.scope.gate +
                                  " or " + other.scope.gate);
  }
  return r;
}

std::vector<std::string> CarriersOf(const DiagnosisState& st,
                                    const std::vector<double>& sd,
                                    const std::vector<Fitted>& fits,
                                    const std::vector<CandidateResult>& results,
                                    int winner) {
  const TermSpec& term = fits[winner].terms.back();
  const std::string& covariate = results[winner].covariate;
  std::vector<std::string> carriers;
  if (CarrierGroupOf(covariate) == nullptr ||
      FamilyOf(term.term.form).names_mechanism()) {
    return carriers;
  }
  for (size_t j = 0; j < fits.size(); ++j) {
    const std::string& other = results[j].covariate;
    if (!fits[j].usable || !(fits[j].rss > 0) ||
        !SameCarriedMechanism(covariate, other) ||
        FamilyOf(fits[j].terms.back().term.form).names_mechanism() ||
        fits[j].terms.back().term.scope.Label() != term.term.scope.Label() ||
        std::find(carriers.begin(), carriers.end(), other) != carriers.end()) {
      continue;
    }
    // The encompassing test of DistinctFromRivals, both ways.
    if (!TiedBothWays(st, sd, fits, winner, static_cast<int>(j))) continue;
    carriers.push_back(other);
  }
  if (!carriers.empty()) carriers.insert(carriers.begin(), covariate);
  return carriers;
}

}  // namespace rollwear::diag
