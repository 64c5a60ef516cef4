// The gates of the diagnosis (docs/diagnosis.md, "A term behind a gate"):
// the gates a gated family's candidates are offered behind, the round's
// refits of one gate per term with its ungated twin, and the guard that a
// gate is required. The other two checks of a gate are the proxy chain's
// siblings (its other side, diagnosis_siblings.cc) and constancy inside it
// (diagnosis_guard.cc, diagnosis_split.cc).
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_internal.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// The same candidate term apart from its gate: covariate, form and place.
bool SameTermApartFromGate(const TermSpec& x, const TermSpec& y) {
  const auto place = [](const TermScope& s) {
    return TermScope(s.stand, s.position, s.roll_type, s.grade);
  };
  return x.covariate == y.covariate && x.term.form == y.term.form &&
         place(x.term.scope) == place(y.term.scope);
}

bool Gated(const Candidate& c) { return !c.spec.term.scope.gate.empty(); }

// The term an item of the round stands for: a candidate's, or a fit's last
// (the candidate it was fitted for); null when the fit holds none.
const TermSpec* TermOf(const Candidate& c) { return &c.spec; }
const TermSpec* TermOf(const Fitted& f) {
  return f.terms.empty() ? nullptr : &f.terms.back();
}
bool GatedTerm(const TermSpec* t) {
  return t != nullptr && !t->term.scope.gate.empty();
}

// Whether item i is gated while a gated copy of the same term is among
// `chosen` (the round takes one gate per term).
template <typename Item>
bool GatedCopyAmong(const std::vector<Item>& items, int i,
                    const std::vector<int>& chosen) {
  const TermSpec* x = TermOf(items[i]);
  if (!GatedTerm(x)) return false;
  return std::any_of(chosen.begin(), chosen.end(), [&](int j) {
    const TermSpec* y = TermOf(items[j]);
    return GatedTerm(y) && SameTermApartFromGate(*x, *y);
  });
}

// Appends to `chosen`, for each gated item in it, the first ungated item of
// the same term that is `eligible` and not chosen yet: its ungated twin.
template <typename Item, typename Eligible>
void AddTwinsOf(const std::vector<Item>& items, Eligible eligible,
                std::vector<int>* chosen) {
  for (size_t k = 0, n = chosen->size(); k < n; ++k) {
    const TermSpec* g = TermOf(items[(*chosen)[k]]);
    if (!GatedTerm(g)) continue;
    for (int i = 0; i < static_cast<int>(items.size()); ++i) {
      const TermSpec* t = TermOf(items[i]);
      if (t != nullptr && !GatedTerm(t) && eligible(i) &&
          SameTermApartFromGate(*t, *g) &&
          std::find(chosen->begin(), chosen->end(), i) == chosen->end()) {
        chosen->push_back(i);
        break;
      }
    }
  }
}

}  // namespace

std::vector<TermScope> GateScopes(const TermData& td,
                                  const std::vector<int>& train,
                                  const DiagnosisThresholds& thresholds,
                                  int covariate) {
  std::vector<TermScope> out;
  for (int k = 0; k < static_cast<int>(td.catalog.size()); ++k) {
    const CovariateSpec& c = td.catalog[k];
    if (k == covariate || c.level != CovariateLevel::kPass ||
        c.kind != CovariateKind::kNumeric ||
        c.source == CovariateSource::kCell || c.accumulates || c.locate_only) {
      continue;
    }
    const WeightedValues values = Collect(td, train, k);
    if (values.v.empty()) continue;
    std::vector<double> edges;
    for (int j = 1; j < thresholds.gate_grid; ++j) {
      const double e =
          Quantile(values, j / static_cast<double>(thresholds.gate_grid));
      // An edge at the smallest value leaves nothing below it (the gate
      // "below" acts nowhere, "above" everywhere: the ungated twin).
      if (std::isfinite(e) && e > values.v.front().first &&
          std::find(edges.begin(), edges.end(), e) == edges.end()) {
        edges.push_back(e);
      }
    }
    // Without ties each side holds 1/gate_grid of the load-weighted passes
    // or more; with ties at least the passes of one value (a reading holds
    // passes on both sides, so readings are not counted as a place's are).
    for (double e : edges) {
      for (bool above : {true, false}) {
        TermScope s;
        s.gate = c.name;
        s.gate_at = e;
        s.gate_above = above;
        out.push_back(s);
      }
    }
  }
  return out;
}

bool GateOfATermIn(const std::vector<Candidate>& candidates, int i,
                   const std::vector<int>& chosen) {
  return GatedCopyAmong(candidates, i, chosen);
}

void AddUngatedTwins(const std::vector<Candidate>& candidates,
                     std::vector<int>* chosen) {
  AddTwinsOf(
      candidates, [](int) { return true; }, chosen);
}

void AddRivalGates(const std::vector<Candidate>& candidates,
                   const std::vector<double>& score_p, double max_score_p,
                   std::vector<int>* chosen) {
  for (size_t k = 0, n = chosen->size(); k < n; ++k) {
    const int g = (*chosen)[k];
    if (!Gated(candidates[g])) continue;
    const std::string& gate = candidates[g].spec.term.scope.gate;
    // The strongest gate of the same term on each other gate covariate.
    std::vector<int> best;
    for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
      const TermScope& s = candidates[i].spec.term.scope;
      if (!Gated(candidates[i]) || s.gate == gate ||
          !(score_p[i] <= max_score_p) ||
          !SameTermApartFromGate(candidates[i].spec, candidates[g].spec)) {
        continue;
      }
      auto same = std::find_if(best.begin(), best.end(), [&](int b) {
        return candidates[b].spec.term.scope.gate == s.gate;
      });
      if (same == best.end()) {
        best.push_back(i);
      } else if (score_p[i] < score_p[*same]) {
        *same = i;
      }
    }
    for (int i : best) {
      if (std::find(chosen->begin(), chosen->end(), i) == chosen->end())
        chosen->push_back(i);
    }
  }
}

bool GatedCopyIn(const std::vector<Fitted>& fits, int i,
                 const std::vector<int>& chosen) {
  return GatedCopyAmong(fits, i, chosen);
}

int UngatedTwinOf(const std::vector<Fitted>& fits, int gated) {
  const TermSpec* g = TermOf(fits[gated]);
  if (!GatedTerm(g)) return -1;
  for (size_t j = 0; j < fits.size(); ++j) {
    const TermSpec* t = TermOf(fits[j]);
    if (fits[j].usable && t != nullptr && !GatedTerm(t) &&
        SameTermApartFromGate(*t, *g))
      return static_cast<int>(j);
  }
  return -1;
}

void AddFittedTwins(const std::vector<Fitted>& fits,
                    const std::vector<CandidateResult>& results, double alpha,
                    std::vector<int>* chosen) {
  AddTwinsOf(
      fits,
      [&](int i) { return fits[i].usable && results[i].p_adjusted < alpha; },
      chosen);
}

// A gate must be required: the gated term added to the model that holds
// the same term on every pass (its ungated twin, fitted from no effect)
// must add significantly, LR = n ln(RSS_open / RSS_open+gated) ~ chi2(df)
// (Wilks 1938), at thresholds.alternative_alpha with a Bonferroni factor of the
// thresholds the candidate was offered behind (GateScopes: the threshold
// was chosen among them; given the twin, the two sides of a threshold are
// one model). A fit that fails refuses: not checked is not passed. Otherwise
// the effect acts on every pass as well and "elsewhere the wear law holds" is
// not shown: refused, and the ungated term stays on offer (the simulator's
// plain lubrication flag was named behind a gate on shift_mm).
GuardResult GateRequired(const DiagnosisState& st,
                         const DiagnosisOptions& options,
                         const std::vector<double>& sd,
                         const Fitted& with_term) {
  const TermSpec& spec = with_term.terms.back();
  if (spec.term.scope.gate.empty()) return GuardResult{};
  Fitted without = with_term;
  without.terms.pop_back();
  TermSpec open = spec;
  open.term.scope.gate.clear();
  std::fill(open.term.params.begin(), open.term.params.end(), 0.0);
  const Fitted base = FitWith(st, sd, without, open);
  const Fitted joint =
      base.usable && base.rss > 0 ? FitWith(st, sd, base, spec) : Fitted{};
  GuardResult r;
  if (!joint.usable || !(joint.rss > 0)) {
    // Not checked is not passed.
    r.pass = false;
    r.reason = "whether its gate is required cannot be checked (a fit failed)";
    return r;
  }
  const Encompassing e = Encompassed(st, base, joint, spec.term.NumParams());
  const double lr = e.lr;
  // Given the twin, a gate above a threshold and the gate below it are one
  // model (flag 1[below] = flag - flag 1[above]): one test per threshold,
  // and the gate is required when the one chosen adds (AnyOf).
  const Multiplicity gates = AnyOf(
      options.thresholds,
      static_cast<double>(
          GateScopes(st.td, st.train, st.thresholds, spec.covariate).size() /
          2));
  if (gates.Rejects(e.p)) return GuardResult{};
  r.pass = false;
  char buf[240];
  std::snprintf(buf, sizeof(buf),
                "its gate is not required: the same term on every pass fits "
                "as well (given it, the gate adds LR %.1f, p adjusted %.2g)",
                lr, gates.Adjusted(e.p));
  r.reason = buf;
  return r;
}

}  // namespace rollwear::diag
