// The round's winner chosen through the guards (docs/diagnosis.md, "The
// proxy guard"): the candidates in order of their tests, each refused by
// the proxy guard (diagnosis_guard.cc), by a cell it is no better than, or
// as fitting worse than a candidate the guard refused, until one passes;
// the places the refused ones located are kept for the verdict.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {

namespace {

// Adds `u` to `located` unless the same place is there. Collinear rivals
// refused in turn (test encompassing_lr, same scope) describe one
// structure: one entry, whose `where` lists every covariate along which it
// lives.
void AddLocated(const Unexplained& u, std::vector<Unexplained>* located) {
  auto scope_of = [](const std::string& where) {
    return where.substr(0, where.rfind(": along "));
  };
  // The covariates an entry lives along: "<scope>: along a or b or c".
  auto along = [](const std::string& where) {
    std::vector<std::string> out;
    size_t at = where.rfind(": along ");
    if (at == std::string::npos) return out;
    std::string rest = where.substr(at + 8);
    for (size_t sep; (sep = rest.find(" or ")) != std::string::npos;) {
      out.push_back(rest.substr(0, sep));
      rest = rest.substr(sep + 4);
    }
    out.push_back(rest);
    return out;
  };
  for (Unexplained& v : *located) {
    if (v.test == "encompassing_lr" && u.test == v.test &&
        scope_of(v.where) == scope_of(u.where)) {
      const std::vector<std::string> listed = along(v.where);
      if (std::find(listed.begin(), listed.end(), u.dimension) == listed.end())
        v.where += " or " + u.dimension;
      return;
    }
    if (v.dimension == u.dimension && v.where == u.where) return;
  }
  located->push_back(u);
}

// The proxy guard's comparison with the best factor cell (issue 15): a
// winner that is not itself a cell must explain something an accepted cell
// candidate of the round does not. Nested likelihood-ratio test of the
// winner's term given the cell, LR = n ln(RSS_cell / RSS_cell+term) ~
// chi2(df), Bonferroni over the round's `num_tests`. When it is not
// significant the two describe the same structure (e.g. a contact length
// term on one roll type whose contact length differs between the two stands
// it runs in, against that roll type's cell at one stand), and the
// structural description is preferred: a factor combination the K structure
// cannot express needs no covariate to be true. Returns why the winner is
// not named, or "" when it is distinct from every accepted cell.
std::string NoBetterThanCell(const DiagnosisState& st,
                             const std::vector<double>& sd,
                             const std::vector<int>& accepted,
                             const std::vector<Fitted>& fits, int winner,
                             double num_tests,
                             const DiagnosisOptions& options) {
  const TermSpec& term = fits[winner].terms.back();
  if (term.term.form == TermForm::kCell || term.term.IsMeasurementTerm())
    return "";
  // The winner's own effect tested again, given the cell: one of the
  // round's tests.
  const Multiplicity round = RoundFamily(options, num_tests);
  for (int j : accepted) {
    const TermSpec& cell = fits[j].terms.back();
    if (j == winner || cell.term.form != TermForm::kCell) continue;
    const Encompassing e = Encompass(st, sd, fits[j], term);
    if (!e.with.usable) continue;
    if (!round.Rejects(e.p)) {
      char buf[200];
      std::snprintf(buf, sizeof(buf),
                    "no better than the cell %s (given the cell: LR %.1f, "
                    "p adjusted %.2g)",
                    cell.term.scope.Label().c_str(), e.lr, round.Adjusted(e.p));
      return buf;
    }
  }
  return "";
}

}  // namespace

// The proxy guard's comparison with what it refused (issue 15): a candidate
// that passes, ranked below a candidate the guard refused (inconsistent
// across a dimension, living between groups, leaving the located structure,
// not taking the autocorrelation along time) is a shadow of that structure
// when the refused one fits the training data clearly better. Both add the
// same kind of term to the same model; with p_w and p_r parameters,
// Delta = n ln(RSS_winner / RSS_refused) - 2 (p_r - p_w) (Akaike 1974, IEEE
// TAC 19:716, as a difference of AIC) above the chi2(1) 1 % point says the
// refused description holds clearly more of the mismatch, and the winner's
// passing the guard is only its lower power: e.g. a temperature x speed
// interaction, refused as a temperature effect inconsistent across the
// quartiles of rolled length, then read as a specific-force effect at F7.
// Every refused candidate is compared (the largest Delta is reported). The
// 6.63 is a chosen cut, not a test level: the two models are not nested,
// and a cell's RSS carries its prior's pseudo-residual, which only makes a
// cell look worse here (so the check can only withhold a cell's name).
GuardResult FitsWorseThanRefused(const DiagnosisState& st,
                                 const std::vector<Fitted>& fits, int winner,
                                 const std::vector<int>& refused,
                                 const std::vector<CandidateResult>& results) {
  GuardResult r;
  const double n = static_cast<double>(st.train.size());
  double worst = st.thresholds.shadow_delta;
  int by = -1;
  for (int j : refused) {
    const double extra = fits[j].terms.back().term.NumParams() -
                         fits[winner].terms.back().term.NumParams();
    const double delta =
        n * std::log(fits[winner].rss / fits[j].rss) - 2 * extra;
    if (delta > worst) {
      worst = delta;
      by = j;
    }
  }
  if (by < 0) return r;
  char buf[240];
  std::snprintf(
      buf, sizeof(buf),
      "fits worse than %s, which the guard refused (AIC difference %.1f): a "
      "shadow of the structure that candidate could not describe",
      results[by].covariate.c_str(), worst);
  r.pass = false;
  r.reason = buf;
  return r;
}

namespace {

// What the winner's guards see: the round and the candidate tried.
struct WinnerGuardContext {
  const Dataset& data;
  const DiagnosisOptions& options;
  const DiagnosisState& st;
  const std::vector<double>& sd;
  const std::vector<int>& accepted;
  const std::vector<Fitted>& fits;
  const std::vector<CandidateResult>& results;
  double num_tests;
  const std::vector<Breakdown>& before;  // Locate on the training data
  const std::vector<int>& refused;       // candidates refused as proxies
  const std::vector<std::string>& refused_covariates;  // theirs
  int candidate;
};

// One guard of a round's winner: the refusal it gives and its check.
struct WinnerGuard {
  RefusalKind kind;
  GuardResult (*check)(const WinnerGuardContext&);
};

// The guards a round's winner must pass to be named, in order; the first
// refusal stops the chain (docs/diagnosis.md, "The proxy guard"): the
// vocabulary first (a quantity the format names; a fit inside its box),
// then the places and rivals the effect may stand in for.
constexpr WinnerGuard kWinnerGuards[] = {
    {RefusalKind::kNotNameable,
     [](const WinnerGuardContext& c) {
       return NotNameable(c.st, c.fits, c.results, c.candidate);
     }},
    {RefusalKind::kAtBoxBound,
     [](const WinnerGuardContext& c) {
       return AtBoxBound(c.st, c.fits, c.results, c.candidate);
     }},
    {RefusalKind::kNoBetterThanCell,
     [](const WinnerGuardContext& c) {
       GuardResult g;
       g.reason = NoBetterThanCell(c.st, c.sd, c.accepted, c.fits, c.candidate,
                                   c.num_tests, c.options);
       g.pass = g.reason.empty();
       return g;
     }},
    {RefusalKind::kProxyGuard,
     [](const WinnerGuardContext& c) {
       return GuardAgainstProxy(c.data, c.st, c.options, c.sd, c.before,
                                c.fits[c.candidate], c.num_tests,
                                c.refused_covariates);
     }},
    {RefusalKind::kNotDistinguishable,
     [](const WinnerGuardContext& c) {
       return DistinctFromRivals(c.st, c.sd, c.accepted, c.fits, c.results,
                                 c.candidate);
     }},
    {RefusalKind::kNotDistinguishable,
     [](const WinnerGuardContext& c) {
       return DistinctFromOtherGates(c.st, c.sd, c.fits, c.results,
                                     c.candidate);
     }},
    {RefusalKind::kShadowOfRefused,
     [](const WinnerGuardContext& c) {
       if (c.refused.empty()) return GuardResult{};
       return FitsWorseThanRefused(c.st, c.fits, c.candidate, c.refused,
                                   c.results);
     }},
};

// Runs kWinnerGuards on `c.candidate` until one refuses; `kind` gets the
// refusing guard's RefusalKind (the last one's when all pass).
GuardResult RunWinnerGuards(const WinnerGuardContext& c, RefusalKind* kind) {
  GuardResult g;
  *kind = RefusalKind::kUnspecified;
  for (const WinnerGuard& guard : kWinnerGuards) {
    g = guard.check(c);
    *kind = guard.kind;
    if (!g.pass) break;
  }
  return g;
}

// Locate on the training data under st.current, residuals clipped to sd.
std::vector<Breakdown> LocateBefore(const Dataset& data,
                                    const DiagnosisOptions& options,
                                    const DiagnosisState& st,
                                    const std::vector<double>& sd) {
  std::vector<double> clip;
  for (int o : st.train) clip.push_back(sd[o]);
  return Locate(
      st.td, data, st.train,
      PredictTerms(st.td, st.train, st.current.log_k, st.current.terms),
      options.thresholds, &clip);
}

}  // namespace

// See diagnosis_stages_internal.h.
GuardResult WinnerGuardsOn(
    const Dataset& data, const DiagnosisOptions& options,
    const DiagnosisState& st, const std::vector<double>& sd,
    const std::vector<int>& accepted, const std::vector<Fitted>& fits,
    const std::vector<CandidateResult>& results, double num_tests,
    const std::vector<std::string>& refused_covariates, int candidate) {
  const std::vector<Breakdown> before = LocateBefore(data, options, st, sd);
  const std::vector<int> none;
  const WinnerGuardContext context{
      data,    options,   st,     sd,   accepted,           fits,
      results, num_tests, before, none, refused_covariates, candidate};
  RefusalKind kind;
  return RunWinnerGuards(context, &kind);
}

// See diagnosis_stages_internal.h.
int GuardedWinner(int round, const Dataset& data,
                  const DiagnosisOptions& options, const DiagnosisState& st,
                  const std::vector<double>& sd,
                  const std::vector<int>& accepted,
                  const std::vector<Fitted>& fits,
                  const std::vector<CandidateResult>& results, double num_tests,
                  DiagnosisReport* report, RoundRefusals* refusals) {
  if (accepted.empty()) return -1;
  const std::vector<Breakdown> before = LocateBefore(data, options, st, sd);
  std::vector<Unexplained>& located = refusals->located;
  std::vector<int>& refused = refusals->refused;  // refused as proxies
  std::vector<std::string>& refused_covariates = refusals->refused_covariates;
  for (int i : accepted) {
    // A locate-only covariate is a structure the vocabulary cannot name:
    // refused like an inconsistent effect (what fits worse is its shadow).
    const WinnerGuardContext context{
        data,    options,   st,     sd,      accepted,           fits,
        results, num_tests, before, refused, refused_covariates, i};
    RefusalKind kind;
    GuardResult g = RunWinnerGuards(context, &kind);
    if (g.pass) return i;
    const bool by_cell = kind == RefusalKind::kNoBetterThanCell;
    const bool by_rival = kind == RefusalKind::kNotDistinguishable;
    // A cell or a rival that describes the same data is not a structure
    // the vocabulary failed on: not a reason to call the others shadows;
    // nor a fit stopped at its box's edge, whose good fit is what its form
    // stands in for (per_coil:0 + run_in: the true wear per coil was
    // refused as its shadow).
    const bool by_bound = kind == RefusalKind::kAtBoxBound;
    // Nor a gate the term on every pass does without: the ungated twin
    // describes the same data (lubrication seed 102: the plain flag was
    // refused as a shadow of its own gated copy).
    const bool by_twin = g.guard == "gate_required";
    if (!by_cell && !by_rival && !by_bound && !by_twin) {
      refused.push_back(i);
      refused_covariates.push_back(results[i].covariate);
    }
    const CandidateResult& c = results[i];
    // A refusal that locates the candidate's own effect leaves its
    // adjusted p to the round (PartNotRequired).
    if (std::isnan(g.located.p_adjusted)) g.located.p_adjusted = c.p_adjusted;
    refusals->rows.push_back(report->runners_up.size());
    report->runners_up.push_back({round, c.covariate, c.form, c.p_adjusted,
                                  c.cv_mse_ratio, g.reason, kind, g.guard});
    refusals->tried.push_back(i);
    refusals->kinds.push_back(kind);
    refusals->guards.push_back(g.guard);
    refusals->reasons.push_back(g.reason);
    refusals->places.push_back(g.located);
    if (!g.located.dimension.empty()) AddLocated(g.located, &located);
  }
  return -1;
}

}  // namespace rollwear::diag
