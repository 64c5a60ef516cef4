// Joint forward selection (docs/diagnosis.md, "Two effects together"): a
// candidate the guards refused on the round's model, judged again on the
// model that also carries another significant structure of the round, and
// named when the two are one consistent description (each adds given the
// other and passes every guard on the model with the other); after the
// rounds, such a finding whose partner the final model does not hold is
// withdrawn.
//
// Greedy forward selection judges each candidate on the model of its round.
// With two effects in the data, the one not yet modelled leaves structure
// that a guard reads as the candidate's failing: a hardness term leaving
// "located structure" along the campaign while the campaign's growth is
// unmodelled; a speed term leaving structure along the hours in service
// while the stoppages' effect is unmodelled. Forward selection
// with re-examination of the included terms given the others (Efroymson
// 1960, in Ralston & Wilf, Mathematical Methods for Digital Computers,
// ch. 17) is the classical remedy; here only the guards' verdicts are
// re-examined, and only when the round would otherwise name nothing.
//
// Thread-safety: not reentrant on one state (it swaps st->current for the
// duration of a check and restores it); distinct states are independent.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/fit/term_fit.h"

namespace rollwear::diag {
namespace {

// A refusal that structure left by another effect can cause: the proxy
// chain's looks. Not a rival or a cell describing the same data (given it,
// the candidate adds nothing), a quantity the format does not name, a fit
// at its box's edge, a gate the term does without (gate_required), nor a
// shadow of a refused structure (the context does not hold the refused
// fits the shadow test compares with).
bool StructuralRefusal(RefusalKind kind, const std::string& guard) {
  return kind == RefusalKind::kProxyGuard && guard != "gate_required";
}

// The best-screened candidate of each covariate whose score test is
// significant at the round's level (score p x num_tests < alpha), strongest
// first, at most `limit` (a cost bound: each is refitted).
std::vector<int> StrongestPerCovariate(
    const std::vector<double>& score_p,
    const std::vector<CandidateResult>& results, double alpha, double num_tests,
    int limit) {
  std::vector<int> order(score_p.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return score_p[a] < score_p[b]; });
  std::vector<int> out;
  for (int i : order) {
    if (static_cast<int>(out.size()) >= limit ||
        !(score_p[i] * num_tests < alpha))
      break;
    if (std::none_of(out.begin(), out.end(), [&](int j) {
          return results[j].covariate == results[i].covariate;
        }))
      out.push_back(i);
  }
  return out;
}

// The covariate along which a refusal located the structure left ("inconsistent
// across temperature_c": dimension "effect_by_temperature_c" or
// "temperature_c"), or "" when the place is not along a covariate.
std::string LocatedCovariate(const Unexplained& place, const TermData& td) {
  std::string d = place.dimension;
  if (d.rfind("effect_by_", 0) == 0) d = d.substr(10);
  return td.CovariateIndex(d) >= 0 ? d : "";
}

// The best-screened candidates over `covariate` whose score test is
// significant at the round's level, one per form, strongest first, at
// most `limit` (a form whose fit stops at its box's edge is no context:
// the next may be).
std::vector<int> StrongestOf(const std::string& covariate,
                             const std::vector<double>& score_p,
                             const std::vector<CandidateResult>& results,
                             double alpha, double num_tests, int limit) {
  std::vector<int> order;
  for (size_t i = 0; i < score_p.size(); ++i) {
    if (results[i].covariate == covariate && score_p[i] * num_tests < alpha)
      order.push_back(static_cast<int>(i));
  }
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return score_p[a] < score_p[b]; });
  std::vector<int> out;
  for (int i : order) {
    if (static_cast<int>(out.size()) >= limit) break;
    if (std::none_of(out.begin(), out.end(),
                     [&](int j) { return results[j].form == results[i].form; }))
      out.push_back(i);
  }
  return out;
}

// Of `strongest` (fitted in `fits`), the structures other than
// `covariate`'s (and its mechanism's other carriers) whose term adds
// significantly to the round's model (LR ~ chi2(df), Bonferroni over the
// round's `num_tests`): the best fit over `located` (the covariate the
// candidate's refusal located the left structure along) first, then the
// others best fit first, at most `limit` of them; none over a locate-only
// covariate (it cannot pass the guards given anything).
std::vector<int> Contexts(const DiagnosisState& st,
                          const std::vector<Fitted>& fits,
                          const std::vector<CandidateResult>& results,
                          const std::vector<int>& strongest, double alpha,
                          double num_tests, const std::string& covariate,
                          const std::string& located, int limit) {
  const double n = static_cast<double>(st.train.size());
  std::vector<int> out;
  for (int j : strongest) {
    // Another carrier of the candidate's own mechanism is no second effect.
    if (!fits[j].usable || fits[j].terms.empty() || !(fits[j].rss > 0) ||
        results[j].covariate == covariate ||
        SameCarriedMechanism(results[j].covariate, covariate))
      continue;
    const TermSpec& t = fits[j].terms.back();
    const int k = t.covariate;
    if (k >= 0 && k < static_cast<int>(st.td.catalog.size()) &&
        st.td.catalog[k].locate_only)
      continue;
    // A form standing in for structure it does not describe is no context.
    if (!AtBoxBound(st, fits, results, j).pass) continue;
    const double p = ChiSquareSurvival(NestedLr(n, st.current.rss, fits[j].rss),
                                       t.term.NumParams());
    if (p * num_tests < alpha) out.push_back(j);
  }
  std::sort(out.begin(), out.end(), [&](int a, int b) {
    const bool la = results[a].covariate == located;
    const bool lb = results[b].covariate == located;
    return la != lb ? la : fits[a].rss < fits[b].rss;
  });
  // One over the located covariate beside `limit` others.
  const bool first_located =
      !out.empty() && results[out.front()].covariate == located;
  std::vector<int> kept;
  for (int j : out) {
    const bool is_located = results[j].covariate == located;
    if (is_located
            ? kept.empty() && first_located
            : static_cast<int>(kept.size()) < limit + (first_located ? 1 : 0))
      kept.push_back(j);
  }
  return kept;
}

// The round a check of one pair reads.
struct JointRound {
  const Dataset& data;
  const DiagnosisOptions& options;
  const std::vector<Fitted>& fits;
  const std::vector<CandidateResult>& results;
  // The round's tests times the pairs joint selection may try: the
  // Bonferroni count of "adds significantly given the other".
  double num_tests;
  double round_tests;  // the round's own, for the guards
  const std::vector<std::string>& refused_covariates;
};

// Whether `candidate` is named on the model with `given`'s term: the noise
// model refitted there, the term adds significantly to it (LR = n ln(RSS_base
// / RSS_base+candidate) ~ chi2(df), Wilks 1938, Bonferroni over
// r.num_tests) and passes every guard, against `accepted` and its gated
// copies refitted on that model (a failed refit refuses), with the round's
// refused covariates and the other structure's covariate looked along
// (interacts_with_refused: an interaction of the two is no pair).
bool PassesGiven(const JointRound& r, const std::vector<int>& accepted,
                 int candidate, int given, DiagnosisState* st,
                 std::string* reason, std::string* guard = nullptr) {
  const std::vector<Fitted>& fits = r.fits;
  const std::string& given_cov = r.results[given].covariate;
  std::vector<double> sd;
  const Fitted base = FitWithOwnNoise(*st, r.options, fits[given].log_k,
                                      fits[given].terms, &sd);
  const TermSpec& term = fits[candidate].terms.back();
  std::vector<Fitted> on_base(fits.size());
  if (base.usable) on_base[candidate] = FitWith(*st, sd, base, term);
  const Fitted& with = on_base[candidate];
  if (!base.usable || !with.usable || !(with.rss > 0)) {
    *reason = "a fit on that model failed";
    return false;
  }
  const double n = static_cast<double>(st->train.size());
  const double lr = NestedLr(n, base.rss, with.rss);
  const double p = ChiSquareSurvival(lr, term.term.NumParams());
  if (!(p * r.num_tests < r.options.alpha)) {
    *reason = "it adds nothing significant given the other";
    return false;
  }
  // The fits the guards compare with: the accepted ones (rivals, cells) and,
  // for a gated term, its copies behind other gates; not the other
  // structure itself, nor another form of its covariate.
  std::vector<int> on_accepted = {candidate};
  for (int j = 0; j < static_cast<int>(fits.size()); ++j) {
    if (j == candidate || j == given || !fits[j].usable ||
        fits[j].terms.empty())
      continue;
    const TermSpec& other = fits[j].terms.back();
    if (r.results[j].covariate == given_cov &&
        other.term.form != TermForm::kCell)
      continue;
    const bool is_accepted =
        std::find(accepted.begin(), accepted.end(), j) != accepted.end();
    const bool gated_copy = !term.term.scope.gate.empty() &&
                            !other.term.scope.gate.empty() &&
                            other.covariate == term.covariate;
    if (!is_accepted && !gated_copy) continue;
    on_base[j] = FitWith(*st, sd, base, other);
    if (!on_base[j].usable) {
      *reason = "a comparison's fit on that model failed";
      return false;
    }
    if (is_accepted) on_accepted.push_back(j);
  }
  std::vector<std::string> refused;
  for (const std::string& c : r.refused_covariates) {
    if (c != r.results[candidate].covariate) refused.push_back(c);
  }
  if (std::find(refused.begin(), refused.end(), given_cov) == refused.end())
    refused.push_back(given_cov);
  const Fitted saved = st->current;
  st->current = base;
  const GuardResult g =
      WinnerGuardsOn(r.data, r.options, *st, sd, on_accepted, on_base,
                     r.results, r.round_tests, refused, candidate);
  st->current = saved;
  if (!g.pass) *reason = g.reason;
  if (guard != nullptr) *guard = g.guard;
  return g.pass;
}

// The sentence a jointly named finding gets.
std::string JointNote(const std::string& refusal, const std::string& partner) {
  return " Judged alone it was refused (" + refusal +
         "); on the model that also carries the structure along " + partner +
         " it adds significantly and passes every guard, and that term does "
         "the same given it (joint forward selection): the round names it "
         "first, the next judges the other on the model with it.";
}

// The candidates a context is chosen from: the strongest of each other
// covariate by score, and the strongest forms of each covariate a
// structural refusal located the left structure along (a temperature effect
// left unmodelled refuses the lubrication flag as inconsistent across
// temperature_c, whose score ranks below the flag's scoped and gated
// copies).
std::vector<int> ContextCandidates(const DiagnosisOptions& options,
                                   const std::vector<CandidateResult>& results,
                                   double num_tests,
                                   const std::vector<double>& score_p,
                                   const RoundRefusals& refusals,
                                   const DiagnosisState& st) {
  const DiagnosisThresholds& t = options.thresholds;
  std::vector<int> strongest = StrongestPerCovariate(
      score_p, results, options.alpha, num_tests, t.max_joint_contexts + 1);
  for (size_t k = 0; k < refusals.tried.size(); ++k) {
    if (!StructuralRefusal(refusals.kinds[k], refusals.guards[k])) continue;
    for (int j :
         StrongestOf(LocatedCovariate(refusals.places[k], st.td), score_p,
                     results, options.alpha, num_tests, t.max_joint_contexts)) {
      if (std::find(strongest.begin(), strongest.end(), j) == strongest.end())
        strongest.push_back(j);
    }
  }
  return strongest;
}

}  // namespace

// See diagnosis_stages_internal.h.
int JointWinner(int round, const Dataset& data, const DiagnosisOptions& options,
                const std::vector<double>& sd, const std::vector<int>& accepted,
                const std::vector<Fitted>& round_fits,
                const std::vector<CandidateResult>& results, double num_tests,
                const std::vector<double>& score_p,
                const std::vector<Candidate>& screened,
                const RoundRefusals& refusals, DiagnosisState* st,
                DiagnosisReport* report, std::string* note) {
  const DiagnosisThresholds& t = options.thresholds;
  if (round + 1 >= options.max_findings) return -1;
  bool any = false;
  for (size_t k = 0; k < refusals.tried.size(); ++k)
    any = any || StructuralRefusal(refusals.kinds[k], refusals.guards[k]);
  if (!any || t.max_joint_candidates == 0 || t.max_joint_contexts == 0)
    return -1;
  // The contexts, fitted on the round's model where the round did not
  // refit them.
  std::vector<Fitted> fits = round_fits;
  const std::vector<int> strongest =
      ContextCandidates(options, results, num_tests, score_p, refusals, *st);
  for (int j : strongest) {
    if (!fits[j].usable)
      fits[j] = FitWith(*st, sd, st->current, screened[j].spec);
  }
  const JointRound r{
      data, options, fits, results,
      // A located partner beside the contexts: one pair more
      // per candidate.
      num_tests * t.max_joint_candidates * (t.max_joint_contexts + 1),
      num_tests, refusals.refused_covariates};
  std::vector<std::string> tried;
  for (size_t k = 0; k < refusals.tried.size(); ++k) {
    const int a = refusals.tried[k];
    const std::string& cov = results[a].covariate;
    if (!StructuralRefusal(refusals.kinds[k], refusals.guards[k]) ||
        std::find(tried.begin(), tried.end(), cov) != tried.end())
      continue;
    if (static_cast<int>(tried.size()) >= t.max_joint_candidates) break;
    tried.push_back(cov);
    for (int b :
         Contexts(*st, fits, results, strongest, options.alpha, num_tests, cov,
                  LocatedCovariate(refusals.places[k], st->td),
                  t.max_joint_contexts)) {
      std::string why, guard;
      int named = a;
      if (!PassesGiven(r, accepted, a, b, st, &why, &guard)) {
        // A gate the other structure makes unnecessary: the same term on
        // every pass (the gated copy's twin, which the gate was tested
        // against) is the pair's candidate.
        named = guard == "gate_required" ? UngatedTwinOf(fits, a) : -1;
      }
      // The named one's refusal of this round (a twin the round never
      // tried is not named, and not judged).
      const auto at =
          std::find(refusals.tried.begin(), refusals.tried.end(), named);
      if (at == refusals.tried.end()) continue;
      const size_t kn = static_cast<size_t>(at - refusals.tried.begin());
      if (named != a && !PassesGiven(r, accepted, named, b, st, &why)) continue;
      // The pair must be one description: the other, given the winner.
      if (!PassesGiven(r, accepted, b, named, st, &why)) continue;
      const TermScope& bs = fits[b].terms.back().term.scope;
      *note =
          JointNote(refusals.reasons[kn],
                    results[b].covariate + " (" + results[b].form +
                        (bs.Fields().empty() ? "" : ", " + bs.Label()) + ")");
      st->joint.push_back({round, results[b].covariate, refusals.reasons[kn],
                           fits[b].terms.back().term, refusals.places[kn]});
      // Its refusal of this round is withdrawn.
      report->runners_up.erase(report->runners_up.begin() +
                               static_cast<long>(refusals.rows[kn]));
      return named;
    }
  }
  return -1;
}

namespace {

// Whether the final model holds joint pair `pair`'s partner: a term over its
// covariate (a cell: at its place), or a finding other than the pair's own
// (finding `self`) whose covariate or listed carriers carry its mechanism.
bool HoldsPartner(const DiagnosisState::JointPair& pair, size_t self,
                  const DiagnosisState& st, const DiagnosisReport& report) {
  const ModelTerm& p = pair.partner_term;
  for (const TermSpec& t : st.current.terms) {
    if (p.form == TermForm::kCell
            ? t.term.form == TermForm::kCell && t.term.scope == p.scope
            : t.term.covariate == p.covariate)
      return true;
  }
  for (size_t i = 0; i < report.findings.size(); ++i) {
    const Finding& g = report.findings[i];
    if (i == self) continue;
    if (SameCarriedMechanism(g.covariate, pair.partner) ||
        std::find(g.carriers.begin(), g.carriers.end(), pair.partner) !=
            g.carriers.end())
      return true;
  }
  return false;
}

// Withdraws finding i, named jointly per `pair`, whose partner the final
// model does not hold: its term leaves the model (refitted; when the refit
// fails, the other terms at their current values), its refusal alone is
// restored and its place listed.
void WithdrawJoint(const DiagnosisOptions& options,
                   const DiagnosisState::JointPair& pair, size_t i,
                   DiagnosisState* st, DiagnosisReport* report,
                   std::vector<int>* rounds) {
  const Finding& f = report->findings[i];
  Fitted without = st->current;
  const int at = AdoptedTermIndex(st->current.terms, f);
  if (at >= 0) {
    without.terms.erase(without.terms.begin() + at);
    const Fitted refit =
        FitWithOwnNoise(*st, options, st->current.log_k, without.terms);
    if (refit.usable) without = refit;
  }
  Unexplained place = pair.place;
  if (place.dimension.empty()) {
    // A refusal that located nothing: the effect's own covariate.
    place.dimension = f.covariate;
    place.where = "everywhere: along " + f.covariate;
    place.test = "likelihood_ratio";
    place.statistic = f.lr;
    place.p_value = f.p_value;
  }
  if (std::isnan(place.p_adjusted)) place.p_adjusted = f.p_adjusted;
  WithdrawFinding(i,
                  "withdrawn on the final model: named jointly with " +
                      pair.partner +
                      ", which the final model does not hold; alone it was "
                      "refused (" +
                      pair.reason + ")",
                  RefusalKind::kJointPartnerMissing, "", place, without, st,
                  report, rounds);
}

}  // namespace

// See diagnosis_stages_internal.h.
void WithdrawUnpairedJoint(const DiagnosisOptions& options, DiagnosisState* st,
                           DiagnosisReport* report, std::vector<int>* rounds) {
  // Until nothing moves: a partner may itself be a joint finding withdrawn
  // here. A finding is known by its adoption round (`rounds`, aligned with
  // the findings; a cell finding is reported on its factor, not "cell").
  for (bool again = true; again;) {
    again = false;
    for (const DiagnosisState::JointPair& pair : st->joint) {
      const auto it = std::find(rounds->begin(), rounds->end(), pair.round);
      if (it == rounds->end()) continue;  // withdrawn already
      const size_t i = static_cast<size_t>(it - rounds->begin());
      if (HoldsPartner(pair, i, *st, *report)) continue;
      WithdrawJoint(options, pair, i, st, report, rounds);
      again = true;
      break;
    }
  }
}

}  // namespace rollwear::diag
