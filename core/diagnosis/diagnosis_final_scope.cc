// The siblings guard run again on the final model (docs/diagnosis.md, "The
// proxy guard", row `siblings`): a scoped finding was adopted when the same
// term at the other levels of its factor added nothing to the model of its
// round; with the effects the later rounds adopted in the model, it may.
// Two effects together: wear per coil at F7 and a growth along the
// campaign at both stands; the round that adopts the growth, before wear
// per coil is in the model, sees it at F6 only (at F7 the unmodelled wear
// per coil pulls the other way), and "it applies only to F6; elsewhere the
// wear law holds" is then false. A finding whose siblings join it
// significantly in the final model is withdrawn (its term leaves the model,
// refitted without it) and located where the siblings say, as the cells
// are (diagnosis_complement.cc).
// Thread-safety: reentrant (changes only its arguments).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {

// See diagnosis_stages_internal.h.
int AdoptedTermIndex(const std::vector<TermSpec>& terms, const Finding& f) {
  for (size_t i = 0; i < terms.size(); ++i) {
    const ModelTerm& t = terms[i].term;
    if (t.form == f.term.form && t.covariate == f.term.covariate &&
        t.scope == f.term.scope) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

namespace {

// Withdraws the first finding whose siblings join it in the final model;
// true when it did.
bool WithdrawFirstUnconfined(const DiagnosisOptions& options,
                             DiagnosisState* st, DiagnosisReport* report,
                             std::vector<int>* rounds) {
  const std::vector<double> sd =
      TermNoiseSd(st->td, st->train, st->current.log_k, st->current.terms,
                  nullptr, options.robust);
  for (size_t i = 0; i < report->findings.size(); ++i) {
    const Finding& f = report->findings[i];
    if (f.term.scope.IsAll() || f.term.form == TermForm::kCell) continue;
    const int at = AdoptedTermIndex(st->current.terms, f);
    if (at < 0) continue;
    // The final model with the finding's term last, as the guard reads it.
    std::vector<TermSpec> terms = st->current.terms;
    std::rotate(terms.begin() + at, terms.begin() + at + 1, terms.end());
    const Fitted with = Fit(st->td, st->train, sd, st->current.log_k, terms);
    if (!with.usable) continue;
    const GuardResult g = LookAtSiblings(*st, options, sd, with);
    if (g.pass) continue;
    terms.pop_back();
    const Fitted without = Fit(st->td, st->train, sd, with.log_k, terms);
    if (!without.usable) continue;  // keep what was adopted rather than nothing
    WithdrawFinding(i, "withdrawn on the final model: " + g.reason,
                    RefusalKind::kProxyGuard, "siblings", g.located, without,
                    st, report, rounds);
    return true;
  }
  return false;
}

}  // namespace

void WithdrawUnconfinedScopes(const DiagnosisOptions& options,
                              DiagnosisState* st, DiagnosisReport* report,
                              std::vector<int>* rounds) {
  while (WithdrawFirstUnconfined(options, st, report, rounds)) {
  }
}

}  // namespace rollwear::diag
